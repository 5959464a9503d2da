#pragma once
// Options of the EKF and RTS smoother (filters/ekf.h, filters/rts_smoother.h): the run config's
// `ekf:` section (core/case/run_config.h). Plain struct with documented defaults; validate()
// names the first bad field.

namespace graftnav {

struct EkfOptions {
  double covariance_interval_s = 0.05;  // P propagation interval (accumulated Phi)
  double record_interval_s = 1.0;       // smoother record spacing between GNSS updates
  double gate_probability = 0.999;      // chi-square innovation gate; <= 0 or >= 1: no gate
  int max_consecutive_rejections = 5;   // then the next fix is accepted (avoids lock-out)
  double gnss_std_scale = 1.0;          // R = (scale * std)^2 per axis (seed Eq. 27)
  double gnss_std_floor_m = 0.005;      // lower bound on the GNSS 1-sigma
  double gnss_default_std_m = 0.05;     // used when a fix carries no (or a zero) std
  // Initial 1-sigma when EstimationProblem::initial_sigma is not given.
  double init_pos_std_m = 0.5;
  double init_vel_std_m_s = 0.1;
  double init_roll_pitch_std_rad = 0.1 * 0.017453292519943295;
  double init_heading_std_rad = 0.5 * 0.017453292519943295;
  int output_decimation = 1;  // keep every N-th IMU epoch in the solution
  void validate() const;      // throws std::invalid_argument naming the field
};

}  // namespace graftnav
