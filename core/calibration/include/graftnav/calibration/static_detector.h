#pragma once
// Variance-based static-interval detector (used by the multi-position calibration and to check
// that a lab pose is really static).
//
// For every sample k a centred window of `window_s` gives the per-axis variances of the rates
// omega = dtheta/dt and f = dvel/dt; the statistics are
//   s_gyro(k)  = sqrt(var_x + var_y + var_z) of omega   (rad/s)
//   s_accel(k) = sqrt(var_x + var_y + var_z) of f       (m/s^2).
// Sample k is static when s_gyro <= gyro threshold AND s_accel <= accel threshold. Runs of static
// samples at least `min_duration_s` long (after trimming `trim_s` at each end) are returned.
// Thresholds are absolute, or, when init_static_s > 0, `threshold_factor` times the mean
// statistic over the first init_static_s seconds (which must be static: the Tedaldi et al. 2014
// procedure uses such an initial interval).

#include <cstddef>
#include <string>
#include <vector>

#include "graftnav/nav/types.h"

namespace graftnav {

struct StaticDetectorOptions {
  double window_s = 1.0;
  double gyro_threshold_rad_s = 0.05;  // ~2.9 deg/s; <= 0 disables the gyro test
  double accel_threshold_m_s2 = 0.3;   // <= 0 disables the accel test
  double init_static_s = 0.0;          // > 0: adaptive thresholds from the initial interval
  double threshold_factor = 3.0;
  double min_duration_s = 2.0;
  double trim_s = 0.0;
  // Throws std::invalid_argument naming the field.
  void validate() const;
};

struct StaticInterval {
  std::size_t begin = 0, end = 0;  // sample indices, end exclusive
  double t_begin_s = 0.0, t_end_s = 0.0;
  double duration() const { return t_end_s - t_begin_s; }
};

struct StaticDetection {
  std::vector<StaticInterval> intervals;
  double gyro_threshold_rad_s = 0.0;  // thresholds actually used
  double accel_threshold_m_s2 = 0.0;
  std::vector<double> gyro_stat, accel_stat;  // per-sample statistics (for plots)
};

StaticDetection detectStaticIntervals(const ImuSeries& imu, const StaticDetectorOptions& options);

// Fraction of the samples of `imu` that belong to a static interval (with min_duration_s
// relaxed to 0): used to reject lab poses that were not held still.
double staticFraction(const ImuSeries& imu, const StaticDetectorOptions& options);

}  // namespace graftnav
