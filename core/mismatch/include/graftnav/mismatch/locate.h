#pragma once
// Where the residual departs from noise, and in which motion regime.
//
// Motion regimes are labelled per bin from the reference signals (smoothed over regime_smooth_s):
// stopped (no rotation, no horizontal acceleration, vibration at its floor), turning_left /
// turning_right (yaw rate about body z, FRD: positive = clockwise seen from above = right),
// accelerating / braking (forward specific force about its trend over trend_s), temperature_ramp (tested IMU
// temperature changing), high_vibration (within-bin specific-force scatter well above its floor),
// otherwise cruising. The first matching label in that order wins.
//
// Windows of window_s per channel: the window's mean square of the residual (its global mean
// removed) is compared with a noise reference, the mean square that a low quantile of all windows
// corresponds to under a chi-square law with the effective number of independent samples
// n_eff = n (1 - rho) / (1 + rho) (rho = the residual's lag-1 autocorrelation). A window is flagged
// when its mean square exceeds the (1 - false_alarm) chi-square quantile; consecutive flagged
// windows of a channel are merged. excess_rms = sqrt(mean square - noise mean square).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graftnav/mismatch/common_grid.h"

namespace graftnav {

struct RegimeOptions {
  double smooth_s = 1.0;             // moving-average length of the regime signals (s)
  double trend_s = 30.0;             // forward accel = f_x minus its moving average over this
  double stopped_rate_rad_s = 0.01;  // |omega| below this ...
  double stopped_accel_m_s2 = 0.15;  // ... and |forward accel| below this: stopped
  double turn_rate_rad_s = 0.05;     // |yaw rate| above: turning
  double accel_m_s2 = 0.5;           // |forward accel| above: accelerating / braking
  double temperature_ramp_degC_s = 0.5 / 60.0;
  double vibration_factor = 2.0;    // within-bin scatter above factor x median ...
  double vibration_min_m_s2 = 0.3;  // ... and above this: high_vibration
};

// One label per bin. temperature_degC may be empty.
std::vector<std::string> labelRegimes(const BinnedImu& reference,
                                      const Eigen::VectorXd& temperature_degC,
                                      const RegimeOptions& options = {});

struct LocateOptions {
  double window_s = 10.0;
  double noise_quantile = 0.25;  // quantile of window mean squares taken as the noise level
  double false_alarm = 1e-3;     // per window and channel
  int max_entries = 40;          // the largest excesses are kept
};

struct LocatedSpan {
  int channel = 0;       // residual column, 0..5 (gyro x .. accel z; mismatchChannelNames)
  double t_start = 0.0;  // s (record time tags)
  double t_end = 0.0;
  std::string regime;       // most frequent regime label over the span
  double excess_rms = 0.0;  // SI (rad/s or m/s^2)
};

// Channel names in residual column order.
const std::vector<std::string>& mismatchChannelNames();

// Noise mean square per channel as used by locateResidual (for reports).
Eigen::Matrix<double, 6, 1> windowNoiseLevel(const Eigen::MatrixXd& residual, const GridSpec& grid,
                                             const LocateOptions& options = {});

std::vector<LocatedSpan> locateResidual(const Eigen::MatrixXd& residual, const GridSpec& grid,
                                        const std::vector<std::string>& regimes,
                                        const LocateOptions& options = {},
                                        const Eigen::Matrix<double, 6, 1>* noise_ms = nullptr);

}  // namespace graftnav
