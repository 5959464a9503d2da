#include "graftnav/estimation/solution_sink.h"

namespace graftnav {

void NavSolutionSink::reserve(std::size_t epochs) {
  sol_->states.reserve(epochs);
  sol_->sigma.reserve(epochs);
  sol_->gyro_bias_rad_s.reserve(epochs);
  sol_->accel_bias_m_s2.reserve(epochs);
  sol_->gyro_scale.reserve(epochs);
  sol_->accel_scale.reserve(epochs);
}

void NavSolutionSink::add(const NavState& state, const PvaSigma* sigma,
                          const ImuErrorEstimate& sensors) {
  sol_->states.push_back(state);
  if (sigma) sol_->sigma.push_back(*sigma);
  sol_->gyro_bias_rad_s.push_back(sensors.gyro_bias_rad_s);
  sol_->accel_bias_m_s2.push_back(sensors.accel_bias_m_s2);
  sol_->gyro_scale.push_back(sensors.gyro_scale);
  sol_->accel_scale.push_back(sensors.accel_scale);
}

void NavSolutionSink::addOdometerScale(const OdometerScaleEstimate& estimate) {
  sol_->odometer_scale.push_back(estimate.scale);
  sol_->odometer_scale_std.push_back(estimate.std);
}

}  // namespace graftnav
