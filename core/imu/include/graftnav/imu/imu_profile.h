#pragma once
// Stochastic and deterministic specification of an IMU, in SI units. Files (configs/imu/*.yaml,
// case.yaml) carry the seed's Table 1 units (deg/sqrt(h), m/s/sqrt(h), deg/h, mg, ppm); they are
// converted once, in the parser (core/io/src/imu_profile_io.cpp), never elsewhere.

#include <string>

#include "graftnav/imu/plausible_ranges.h"

namespace graftnav {

struct ImuProfile {
  std::string name;                  // e.g. "POS310-like"
  ImuGrade grade = ImuGrade::kMems;  // a required key of every profile file
  // White noise: angle random walk (rad/sqrt(s)) and velocity random walk (m/s/sqrt(s)).
  double arw_rad_sqrt_s = 0.0;
  double vrw_m_s_sqrt_s = 0.0;
  // Bias instability modelled as first-order Gauss-Markov: 1-sigma (SI) and correlation time.
  double gyro_bias_instability_rad_s = 0.0;
  double accel_bias_instability_m_s2 = 0.0;
  double gyro_bias_corr_time_s = 3600.0;
  double accel_bias_corr_time_s = 3600.0;
  // Scale-factor uncertainty (fraction, 1e-6 = 1 ppm) and its Gauss-Markov correlation time.
  double gyro_scale_std = 0.0;
  double accel_scale_std = 0.0;
  double scale_corr_time_s = 3600.0;
  // Turn-on (initial) bias uncertainty, used as the filter's initial bias covariance; defaults to
  // the bias instability when not given.
  double gyro_bias_initial_std_rad_s = 0.0;
  double accel_bias_initial_std_m_s2 = 0.0;
  // Bias repeatability, turn-on to turn-on (1-sigma, SI): how far the field's bias is from the
  // lab's, drawn per grafted realization (sg/realization.h). Negative: not given, and the bias
  // instability is used (each power-on restarts the Gauss-Markov bias from its stationary
  // distribution, as the simulator does).
  double gyro_bias_repeatability_rad_s = -1.0;
  double accel_bias_repeatability_m_s2 = -1.0;
  // The largest value each error term can take for this sensor class (plausible_ranges.h): the
  // grade's class defaults unless the profile's `plausible_ranges:` block names another class or
  // overrides a bound. Not a noise figure; read by the mismatch finder only.
  PlausibleRanges plausible_ranges;
};

}  // namespace graftnav
