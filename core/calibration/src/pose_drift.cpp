#include "graftnav/calibration/pose_drift.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace graftnav {

PoseDriftEstimate measurePoseDrift(const ImuSeries& e, bool gyro, double window_s,
                                   double separation_s) {
  if (!(window_s > 0.0) || !(separation_s > 0.0))
    throw std::invalid_argument("measurePoseDrift: window_s and separation_s must be > 0, got " +
                                std::to_string(window_s) + ", " + std::to_string(separation_s));
  double duration_s = 0.0;
  for (std::size_t k = 0; k < e.size(); ++k) {
    if (!(e[k].dt_s > 0.0))
      throw std::invalid_argument("measurePoseDrift: sample " + std::to_string(k) +
                                  " has dt_s <= 0");
    duration_s += e[k].dt_s;
  }
  if (duration_s < window_s + separation_s)
    throw std::invalid_argument("measurePoseDrift: static record of " + std::to_string(duration_s) +
                                " s is shorter than window + separation = " +
                                std::to_string(window_s + separation_s) + " s");
  const std::size_t per_window = std::max<std::size_t>(
      2, static_cast<std::size_t>(std::lround(window_s * e.size() / duration_s)));
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
    throw std::invalid_argument("measurePoseDrift: " + std::to_string(windows) + " windows of " +
                                std::to_string(window_s) + " s leave no pair " + std::to_string(m) +
                                " windows apart");
  Eigen::Vector3d D = Eigen::Vector3d::Zero();
  for (std::size_t w = 0; w + m < windows; ++w) D += 0.5 * (mean[w] - mean[w + m]).cwiseAbs2();
  const double n = static_cast<double>(windows - m);
  D /= n;
  PoseDriftEstimate out;
  const Eigen::Vector3d drift2 = (D - white).cwiseMax(0.0);
  out.sigma = drift2.cwiseSqrt();
  for (int a = 0; a < 3; ++a) {
    if (!(drift2[a] > 0.0)) continue;
    const double q = 2.0 * drift2[a] / static_cast<double>(m);
    double sum_cov2 = 0.0;  // sum over pair indices k, l of cov(d_k, d_l)^2, by lag
    for (std::size_t lag = 0; lag < windows - m; ++lag) {
      const double c = q * std::max(0.0, static_cast<double>(m) - static_cast<double>(lag)) +
                       white[a] * (lag == 0 ? 2.0 : (lag == m ? -1.0 : 0.0));
      sum_cov2 += (lag == 0 ? n : 2.0 * (n - static_cast<double>(lag))) * c * c;
    }
    out.dof[a] = 2.0 * drift2[a] * drift2[a] / (sum_cov2 / (2.0 * n * n));
  }
  return out;
}

PoseDriftEstimate pooledOverAxes(const PoseDriftEstimate& p) {
  PoseDriftEstimate out;
  const Eigen::Vector3d v = p.sigma.cwiseAbs2();
  double var_sum = 0.0;  // sum over axes of v_a^2 / dof_a
  for (int a = 0; a < 3; ++a)
    if (v[a] > 0.0 && std::isfinite(p.dof[a])) var_sum += v[a] * v[a] / p.dof[a];
  out.sigma.setConstant(std::sqrt(v.sum() / 3.0));
  out.dof.setConstant(var_sum > 0.0 ? v.sum() * v.sum() / var_sum : INFINITY);
  return out;
}

}  // namespace graftnav
