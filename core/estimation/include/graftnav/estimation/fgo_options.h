#pragma once
// Options of the factor-graph estimators (batch smoother "fgo" and sliding window "fgo-window").
// Plain struct with defaults; validate() names the first bad field. Parsed from the `fgo:`
// section of the run config (core/case/include/graftnav/case/run_config.h).

#include <string>

namespace graftnav {

// Whether the graph's nodes carry gyro and accelerometer scale factors per axis (the EKF's
// states, with the same IMU profile): never, only when vehicle aiding (odometer or NHC) is on,
// or always.
enum class ImuScaleStates { kOff, kWithVehicleAiding, kOn };
// "off" | "with_vehicle_aiding" | "on"; false for anything else.
bool parseImuScaleStates(const std::string& text, ImuScaleStates* out);

// The GNSS factors' loss on the whitened residual norm: Huber, Cauchy, or none (plain squares).
enum class RobustLoss { kHuber, kCauchy, kNone };
// "huber" | "cauchy" | "none"; false for anything else.
bool parseRobustLoss(const std::string& text, RobustLoss* out);

struct FgoOptions {
  // Preintegration.
  bool earth_rotation = true;                 // keep omega_ie in the preintegration factor
  double max_node_spacing_s = 1.0;            // extra nodes where GNSS is absent (outages, gaps)
  double reintegrate_gyro_bias_rad_s = 2e-4;  // re-preintegrate when |bg - bg_lin| exceeds this
  double reintegrate_accel_bias_m_s2 = 2e-2;  // ... or |ba - ba_lin| exceeds this
  int max_reintegration_rounds = 2;           // batch: re-solve rounds after re-preintegration
  // IMU scale-factor states. With vehicle aiding the odometer and NHC hold the along-track and
  // heading errors that a gyro scale error makes in turns during outages; without it the graphs
  // keep the 15-state node (docs/fgo.md).
  ImuScaleStates imu_scale_states = ImuScaleStates::kWithVehicleAiding;

  // GNSS factors.
  RobustLoss robust_loss = RobustLoss::kHuber;
  double robust_loss_scale = 3.0;  // on the whitened residual norm (sigmas)
  double chi2_threshold = 16.27;   // 3 dof, 99.9 %: cull after a first solve
  int culling_rounds = 1;          // solve -> cull -> re-solve rounds
  double gnss_min_std_m = 0.002;   // floor on the fix's stated 1-sigma
  // Culling guards. A solved residual is not an innovation: after an outage the first fixes
  // disagree with the drifted estimate by metres and must pull it back, not be culled.
  double cull_grace_s = 10.0;       // window: no culling this long after a GNSS gap
  int max_consecutive_culls = 3;    // window: then the next fix is kept (as the EKF)
  double max_cull_fraction = 0.05;  // batch: more than this culled -> cull none (report)

  // First-node prior when EstimationProblem::initial_sigma is not given (< 0).
  double initial_position_std_m = 1.0;
  double initial_velocity_std_m_s = 0.1;
  double initial_attitude_std_rad = 0.00873;  // 0.5 deg, about north, east and down

  // Batch solver.
  int max_iterations = 50;
  // Levenberg-Marquardt initial trust-region radius (Ceres default 1e4). Large: the damping
  // diag(J^T J) / radius must stay below the information of GNSS-observed modes although the
  // preintegration factors between 10 Hz nodes are ~1e8 stiffer (see docs/fgo.md).
  double initial_trust_region_radius = 1e12;
  int num_threads = 1;
  bool compute_covariance = false;  // marginal p, v, attitude covariance of every node

  // Sliding window.
  int window_nodes = 10;        // nodes kept in the window
  int window_iterations = 4;    // solver iterations per solve
  int window_solve_stride = 1;  // solve after every n-th new node (1: every node)
  // Batch initialization: a fixed-lag window pass solving every batch_init_stride nodes over a
  // window of 2 * batch_init_stride nodes.
  int batch_init_stride = 1;
  bool window_fixed_lag_output = false;  // output each node when it leaves the window (a
                                         // fixed-lag smoother) instead of when it enters (causal)

  // Floors for noise parameters (keeps the information finite for ideal, error-free IMUs).
  double min_arw_rad_sqrt_s = 1e-7;
  double min_vrw_m_s_sqrt_s = 1e-6;
  double min_gyro_bias_std_rad_s = 1e-9;
  double min_accel_bias_std_m_s2 = 1e-7;
  // Odometer scale factor: each node carries its own, tied to the next by a random walk of at
  // least this (fraction/sqrt(s); 1e-6 moves it by ~40 ppm over 25 min) so that a scale given
  // as constant stays finite.
  double min_odometer_scale_random_walk_per_sqrt_s = 1e-6;
  // IMU scale factors (fraction): floor on the profile's steady-state sigma, which sets their
  // Gauss-Markov factor and the first node's prior (a profile without scale errors gives 0).
  double min_imu_scale_std = 1e-6;

  // True when every field is usable; otherwise false and *error names the field and value.
  bool validate(std::string* error) const;
};

}  // namespace graftnav
