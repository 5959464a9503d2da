#pragma once
// Zero-mean prior on the first node's gyro and accelerometer scale factors (fractions), as the
// EKF's initial covariance: r = (sg / sigma_g, sa / sigma_a). Blocks: sg[3], sa[3].

#include <ceres/sized_cost_function.h>

namespace graftnav {

class ImuScalePriorFactor final : public ceres::SizedCostFunction<6, 3, 3> {
 public:
  // Both sigmas > 0 (fractions).
  ImuScalePriorFactor(double gyro_scale_sigma, double accel_scale_sigma);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  double inv_sigma_g_, inv_sigma_a_;
};

}  // namespace graftnav
