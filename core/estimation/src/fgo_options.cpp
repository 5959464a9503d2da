#include "graftnav/estimation/fgo_options.h"

#include <cmath>
#include <string>

namespace graftnav {
namespace {
bool fail(std::string* error, const std::string& key, double value, const char* rule) {
  if (error) *error = "fgo." + key + " = " + std::to_string(value) + ": " + rule;
  return false;
}
}  // namespace

bool parseImuScaleStates(const std::string& text, ImuScaleStates* out) {
  if (text == "off") {
    *out = ImuScaleStates::kOff;
  } else if (text == "with_vehicle_aiding") {
    *out = ImuScaleStates::kWithVehicleAiding;
  } else if (text == "on") {
    *out = ImuScaleStates::kOn;
  } else {
    return false;
  }
  return true;
}

bool parseRobustLoss(const std::string& text, RobustLoss* out) {
  if (text == "huber") {
    *out = RobustLoss::kHuber;
  } else if (text == "cauchy") {
    *out = RobustLoss::kCauchy;
  } else if (text == "none") {
    *out = RobustLoss::kNone;
  } else {
    return false;
  }
  return true;
}

bool FgoOptions::validate(std::string* error) const {
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!positive(max_node_spacing_s))
    return fail(error, "max_node_spacing_s", max_node_spacing_s, "must be > 0");
  if (!positive(reintegrate_gyro_bias_rad_s))
    return fail(error, "reintegrate_gyro_bias_rad_s", reintegrate_gyro_bias_rad_s, "must be > 0");
  if (!positive(reintegrate_accel_bias_m_s2))
    return fail(error, "reintegrate_accel_bias_m_s2", reintegrate_accel_bias_m_s2, "must be > 0");
  if (max_reintegration_rounds < 0)
    return fail(error, "max_reintegration_rounds", max_reintegration_rounds, "must be >= 0");
  if (!positive(robust_loss_scale))
    return fail(error, "robust_loss_scale", robust_loss_scale, "must be > 0");
  if (!positive(chi2_threshold))
    return fail(error, "chi2_threshold", chi2_threshold, "must be > 0");
  if (culling_rounds < 0) return fail(error, "culling_rounds", culling_rounds, "must be >= 0");
  if (!positive(gnss_min_std_m))
    return fail(error, "gnss_min_std_m", gnss_min_std_m, "must be > 0");
  if (!(cull_grace_s >= 0.0)) return fail(error, "cull_grace_s", cull_grace_s, "must be >= 0");
  if (max_consecutive_culls < 1)
    return fail(error, "max_consecutive_culls", max_consecutive_culls, "must be >= 1");
  if (!(max_cull_fraction >= 0.0 && max_cull_fraction <= 1.0))
    return fail(error, "max_cull_fraction", max_cull_fraction, "must be in [0, 1]");
  if (!positive(initial_position_std_m))
    return fail(error, "initial_position_std_m", initial_position_std_m, "must be > 0");
  if (!positive(initial_velocity_std_m_s))
    return fail(error, "initial_velocity_std_m_s", initial_velocity_std_m_s, "must be > 0");
  if (!positive(initial_attitude_std_rad))
    return fail(error, "initial_attitude_std_rad", initial_attitude_std_rad, "must be > 0");
  if (max_iterations < 1) return fail(error, "max_iterations", max_iterations, "must be >= 1");
  if (!positive(initial_trust_region_radius))
    return fail(error, "initial_trust_region_radius", initial_trust_region_radius, "must be > 0");
  if (num_threads < 1) return fail(error, "num_threads", num_threads, "must be >= 1");
  if (window_nodes < 2) return fail(error, "window_nodes", window_nodes, "must be >= 2");
  if (window_iterations < 1)
    return fail(error, "window_iterations", window_iterations, "must be >= 1");
  if (window_solve_stride < 1)
    return fail(error, "window_solve_stride", window_solve_stride, "must be >= 1");
  if (window_solve_stride >= window_nodes)
    return fail(error, "window_solve_stride", window_solve_stride, "must be < window_nodes");
  if (batch_init_stride < 1)
    return fail(error, "batch_init_stride", batch_init_stride, "must be >= 1");
  if (!positive(min_arw_rad_sqrt_s))
    return fail(error, "min_arw_rad_sqrt_s", min_arw_rad_sqrt_s, "must be > 0");
  if (!positive(min_vrw_m_s_sqrt_s))
    return fail(error, "min_vrw_m_s_sqrt_s", min_vrw_m_s_sqrt_s, "must be > 0");
  if (!positive(min_gyro_bias_std_rad_s))
    return fail(error, "min_gyro_bias_std_rad_s", min_gyro_bias_std_rad_s, "must be > 0");
  if (!positive(min_accel_bias_std_m_s2))
    return fail(error, "min_accel_bias_std_m_s2", min_accel_bias_std_m_s2, "must be > 0");
  if (!positive(min_odometer_scale_random_walk_per_sqrt_s))
    return fail(error, "min_odometer_scale_random_walk_per_sqrt_s",
                min_odometer_scale_random_walk_per_sqrt_s, "must be > 0");
  if (!positive(min_imu_scale_std))
    return fail(error, "min_imu_scale_std", min_imu_scale_std, "must be > 0");
  return true;
}

}  // namespace graftnav
