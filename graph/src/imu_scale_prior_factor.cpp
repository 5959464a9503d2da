#include "graftnav/graph/imu_scale_prior_factor.h"

#include <Eigen/Core>
#include <stdexcept>
#include <string>

namespace graftnav {

ImuScalePriorFactor::ImuScalePriorFactor(double gyro_scale_sigma, double accel_scale_sigma) {
  if (!(gyro_scale_sigma > 0.0) || !(accel_scale_sigma > 0.0)) {
    throw std::invalid_argument("ImuScalePriorFactor: sigmas " + std::to_string(gyro_scale_sigma) +
                                ", " + std::to_string(accel_scale_sigma) + " must be > 0");
  }
  inv_sigma_g_ = 1.0 / gyro_scale_sigma;
  inv_sigma_a_ = 1.0 / accel_scale_sigma;
}

bool ImuScalePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  const double inv[2] = {inv_sigma_g_, inv_sigma_a_};
  for (int b = 0; b < 2; ++b) {
    for (int i = 0; i < 3; ++i) residuals[3 * b + i] = parameters[b][i] * inv[b];
    if (jacobians == nullptr || jacobians[b] == nullptr) continue;
    Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>> J(jacobians[b]);
    J.setZero();
    J.block<3, 3>(3 * b, 0).diagonal().setConstant(inv[b]);
  }
  return true;
}

}  // namespace graftnav
