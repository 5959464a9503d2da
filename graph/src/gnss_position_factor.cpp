#include "graftnav/graph/gnss_position_factor.h"

#include <Eigen/Geometry>

#include "graftnav/nav/rotation.h"
#include "graftnav/graph/right_quaternion_manifold.h"

namespace graftnav {

GnssPositionFactor::GnssPositionFactor(const Eigen::Vector3d& z_w,
                                       const Eigen::Matrix3d& sqrt_info_w,
                                       const Eigen::Vector3d& lever_arm_b, double dt_s)
    : z_w_(z_w), sqrt_info_(sqrt_info_w), lever_b_(lever_arm_b), dt_s_(dt_s) {}

bool GnssPositionFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> p(parameters[0]);
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> v(parameters[2]);
  const Eigen::Matrix3d R = q.toRotationMatrix();
  Eigen::Map<Eigen::Vector3d>{residuals} = sqrt_info_ * (p + R * lever_b_ + v * dt_s_ - z_w_);
  if (jacobians == nullptr) return true;
  using Mat33R = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  using Mat34R = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
  if (jacobians[0]) Eigen::Map<Mat33R>{jacobians[0]} = sqrt_info_;
  if (jacobians[1]) {
    // R Exp(d) l ~= R l + R (d x l) = R l - R [l]x d.
    const Eigen::Matrix3d J_t = -sqrt_info_ * R * skew(lever_b_);
    Eigen::Map<Mat34R>{jacobians[1]} = J_t * tangentToAmbientJacobian(q);
  }
  if (jacobians[2]) Eigen::Map<Mat33R>{jacobians[2]} = sqrt_info_ * dt_s_;
  return true;
}

}  // namespace graftnav
