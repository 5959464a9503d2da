#include "graftnav/graph/odometer_scale_factor.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {

OdometerScaleWalkFactor::OdometerScaleWalkFactor(double random_walk_per_sqrt_s, double dt_s) {
  if (!(random_walk_per_sqrt_s > 0.0) || !(dt_s > 0.0)) {
    throw std::invalid_argument("OdometerScaleWalkFactor: random walk " +
                                std::to_string(random_walk_per_sqrt_s) + " and dt " +
                                std::to_string(dt_s) + " must be positive");
  }
  inv_sigma_ = 1.0 / (random_walk_per_sqrt_s * std::sqrt(dt_s));
}

bool OdometerScaleWalkFactor::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  residuals[0] = (parameters[1][0] - parameters[0][0]) * inv_sigma_;
  if (jacobians) {
    if (jacobians[0]) jacobians[0][0] = -inv_sigma_;
    if (jacobians[1]) jacobians[1][0] = inv_sigma_;
  }
  return true;
}

OdometerScalePriorFactor::OdometerScalePriorFactor(double s0, double sigma0) : s0_(s0) {
  if (!(sigma0 > 0.0)) {
    throw std::invalid_argument("OdometerScalePriorFactor: sigma " + std::to_string(sigma0) +
                                " must be positive");
  }
  inv_sigma_ = 1.0 / sigma0;
}

bool OdometerScalePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  residuals[0] = (parameters[0][0] - s0_) * inv_sigma_;
  if (jacobians && jacobians[0]) jacobians[0][0] = inv_sigma_;
  return true;
}

}  // namespace graftnav
