#include "graftnav/imu/imu_error_terms.h"

#include <cmath>
#include <stdexcept>

namespace graftnav {

VibrationRegressor::VibrationRegressor(double window_s) : window_s_(window_s) {
  if (!(window_s_ > 0.0) || !std::isfinite(window_s_)) {
    throw std::invalid_argument("VibrationRegressor: window_s = " + std::to_string(window_s_) +
                                " must be finite and > 0");
  }
}

bool VibrationRegressor::isKnownName(const std::string& name) {
  return name == "specific_force_hp_sq" || name == "angular_rate_hp_sq";
}

bool VibrationRegressor::usesAngularRate(const std::string& name) {
  return name == "angular_rate_hp_sq";
}

void VibrationRegressor::reset() {
  lp_.setZero();
  r_ = 0.0;
  started_ = false;
}

double VibrationRegressor::update(const Eigen::Vector3d& x, double dt_s) {
  if (!started_) {
    lp_ = x;
    r_ = 0.0;
    started_ = true;
    return r_;
  }
  const double a = -std::expm1(-dt_s / window_s_);
  lp_ += a * (x - lp_);
  const double hp_sq = (x - lp_).squaredNorm();
  r_ += a * (hp_sq - r_);
  return r_;
}

}  // namespace graftnav
