#include "graftnav/core/calibration/pose_drift.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace graftnav {

Eigen::Vector3d poseDriftSigma(const ImuSeries& e, bool gyro, double window_s, double separation_s) {
  if (!(window_s > 0.0) || !(separation_s > 0.0))
    throw std::invalid_argument("poseDriftSigma: window_s and separation_s must be > 0, got " +
                                std::to_string(window_s) + ", " + std::to_string(separation_s));
  double duration_s = 0.0;
  for (std::size_t k = 0; k < e.size(); ++k) {
    if (!(e[k].dt_s > 0.0))
      throw std::invalid_argument("poseDriftSigma: sample " + std::to_string(k) + " has dt_s <= 0");
    duration_s += e[k].dt_s;
  }
  if (duration_s < window_s + separation_s)
    throw std::invalid_argument("poseDriftSigma: static record of " + std::to_string(duration_s) +
                                " s is shorter than window + separation = " +
                                std::to_string(window_s + separation_s) + " s");
  const std::size_t per_window =
      std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(window_s * e.size() / duration_s)));
  const std::size_t windows = e.size() / per_window;
  const std::size_t m = std::max<long>(1, std::lround(separation_s / window_s));
  std::vector<Eigen::Vector3d> mean(windows);
  Eigen::Vector3d white = Eigen::Vector3d::Zero();
  for (std::size_t w = 0; w < windows; ++w) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero(), s2 = Eigen::Vector3d::Zero();
    for (std::size_t k = w * per_window; k < (w + 1) * per_window; ++k) {
      const Eigen::Vector3d r = (gyro ? e[k].dtheta_rad : e[k].dvel_m_s) / e[k].dt_s;
      s += r;
      s2 += r.cwiseProduct(r);
    }
    const double n = static_cast<double>(per_window);
    mean[w] = s / n;
    white += (s2 / n - mean[w].cwiseProduct(mean[w])) * (n / (n - 1.0)) / n;  // var of the mean
  }
  white /= static_cast<double>(windows);
  if (windows <= m)
    throw std::invalid_argument("poseDriftSigma: " + std::to_string(windows) + " windows of " +
                                std::to_string(window_s) + " s leave no pair " + std::to_string(m) +
                                " windows apart");
  Eigen::Vector3d D = Eigen::Vector3d::Zero();
  for (std::size_t w = 0; w + m < windows; ++w) D += 0.5 * (mean[w] - mean[w + m]).cwiseAbs2();
  D /= static_cast<double>(windows - m);
  return (D - white).cwiseMax(0.0).cwiseSqrt();
}

}  // namespace graftnav
