#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/calibration/static_detector.h"

namespace graftnav {
namespace {

void require(bool ok, const std::string& field, double value, const char* why) {
  if (!ok)
    throw std::invalid_argument("StaticDetectorOptions: " + field + " = " + std::to_string(value) +
                                " " + why);
}

// Centred moving sqrt(sum of per-axis variances) of the rate signals, via prefix sums.
std::vector<double> movingStd(const ImuSeries& imu, bool gyro, std::size_t half) {
  const std::size_t n = imu.size();
  std::vector<Eigen::Vector3d> c1(n + 1, Eigen::Vector3d::Zero()),
      c2(n + 1, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d x = (gyro ? imu[k].dtheta_rad : imu[k].dvel_m_s) / imu[k].dt_s;
    c1[k + 1] = c1[k] + x;
    c2[k + 1] = c2[k] + x.cwiseProduct(x);
  }
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k >= half ? k - half : 0, b = std::min(n, k + half + 1);
    const double m = static_cast<double>(b - a);
    const Eigen::Vector3d mean = (c1[b] - c1[a]) / m;
    const Eigen::Vector3d var = ((c2[b] - c2[a]) / m - mean.cwiseProduct(mean)).cwiseMax(0.0);
    out[k] = std::sqrt(var.sum());
  }
  return out;
}

}  // namespace

void StaticDetectorOptions::validate() const {
  require(window_s > 0.0, "window_s", window_s, "must be > 0");
  require(init_static_s >= 0.0, "init_static_s", init_static_s, "must be >= 0");
  require(threshold_factor > 0.0, "threshold_factor", threshold_factor, "must be > 0");
  require(min_duration_s >= 0.0, "min_duration_s", min_duration_s, "must be >= 0");
  require(trim_s >= 0.0, "trim_s", trim_s, "must be >= 0");
  require(gyro_threshold_rad_s > 0.0 || accel_threshold_m_s2 > 0.0 || init_static_s > 0.0,
          "gyro_threshold_rad_s", gyro_threshold_rad_s, "and accel_threshold_m_s2 both disabled");
}

StaticDetection detectStaticIntervals(const ImuSeries& imu, const StaticDetectorOptions& opt) {
  opt.validate();
  if (imu.size() < 3) throw std::invalid_argument("detectStaticIntervals: fewer than 3 samples");
  for (std::size_t k = 0; k < imu.size(); ++k)
    if (!(imu[k].dt_s > 0.0))
      throw std::invalid_argument("detectStaticIntervals: sample " + std::to_string(k) +
                                  " has dt_s <= 0");
  const double dt = (imu.back().t_s - imu.front().t_s) / static_cast<double>(imu.size() - 1);
  const std::size_t half =
      std::max<std::size_t>(1, static_cast<std::size_t>(0.5 * opt.window_s / dt));
  StaticDetection det;
  det.gyro_stat = movingStd(imu, true, half);
  det.accel_stat = movingStd(imu, false, half);
  det.gyro_threshold_rad_s = opt.gyro_threshold_rad_s;
  det.accel_threshold_m_s2 = opt.accel_threshold_m_s2;
  if (opt.init_static_s > 0.0) {
    const double t_end = imu.front().t_s + opt.init_static_s;
    double sg = 0.0, sa = 0.0;
    std::size_t m = 0;
    for (std::size_t k = half; k < imu.size() && imu[k].t_s <= t_end - 0.5 * opt.window_s;
         ++k, ++m) {
      sg += det.gyro_stat[k];
      sa += det.accel_stat[k];
    }
    if (m == 0)
      throw std::invalid_argument("detectStaticIntervals: init_static_s = " +
                                  std::to_string(opt.init_static_s) + " shorter than the window");
    det.gyro_threshold_rad_s = opt.threshold_factor * sg / m;
    det.accel_threshold_m_s2 = opt.threshold_factor * sa / m;
  }
  auto isStatic = [&](std::size_t k) {
    return (det.gyro_threshold_rad_s <= 0.0 || det.gyro_stat[k] <= det.gyro_threshold_rad_s) &&
           (det.accel_threshold_m_s2 <= 0.0 || det.accel_stat[k] <= det.accel_threshold_m_s2);
  };
  std::size_t k = 0;
  while (k < imu.size()) {
    if (!isStatic(k)) {
      ++k;
      continue;
    }
    std::size_t e = k;
    while (e < imu.size() && isStatic(e)) ++e;
    // [k, e) static: trim and keep when long enough.
    double t0 = imu[k].t_s - imu[k].dt_s + opt.trim_s, t1 = imu[e - 1].t_s - opt.trim_s;
    std::size_t a = k, b = e;
    while (a < b && imu[a].t_s - imu[a].dt_s < t0 - 1e-12) ++a;
    while (b > a && imu[b - 1].t_s > t1 + 1e-12) --b;
    if (b > a + 1) {
      StaticInterval iv{a, b, imu[a].t_s - imu[a].dt_s, imu[b - 1].t_s};
      if (iv.duration() >= opt.min_duration_s) det.intervals.push_back(iv);
    }
    k = e;
  }
  return det;
}

double staticFraction(const ImuSeries& imu, const StaticDetectorOptions& options) {
  StaticDetectorOptions o = options;
  o.min_duration_s = 0.0;
  o.trim_s = 0.0;
  const StaticDetection d = detectStaticIntervals(imu, o);
  std::size_t n = 0;
  for (const auto& iv : d.intervals) n += iv.end - iv.begin;
  return static_cast<double>(n) / static_cast<double>(imu.size());
}

}  // namespace graftnav
