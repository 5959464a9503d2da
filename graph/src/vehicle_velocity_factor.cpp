#include "graftnav/graph/vehicle_velocity_factor.h"

#include <Eigen/Geometry>
#include <stdexcept>

#include "graftnav/graph/right_quaternion_manifold.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

int VehicleObservation::rows() const {
  return (has_speed && row_std_m_s.x() > 0.0 ? 1 : 0) + (row_std_m_s.y() > 0.0 ? 1 : 0) +
         (row_std_m_s.z() > 0.0 ? 1 : 0);
}

VehicleVelocityFactor::VehicleVelocityFactor(const VehicleObservation& obs,
                                             const Eigen::Matrix3d& C_vb,
                                             const Eigen::Vector3d& lever_arm_b_m,
                                             const Eigen::Vector3d& omega_ie_w, bool with_scale)
    : obs_(obs), C_vb_(C_vb), lever_b_(lever_arm_b_m), omega_ie_w_(omega_ie_w) {
  int m = 0;
  const bool forward = obs.has_speed && obs.row_std_m_s.x() > 0.0;
  if (forward) rows_[m++] = 0;
  for (int i = 1; i < 3; ++i)
    if (obs.row_std_m_s(i) > 0.0) rows_[m++] = i;
  if (m == 0) throw std::invalid_argument("VehicleVelocityFactor: no row to measure");
  uses_scale_ = with_scale && forward;
  set_num_residuals(m);
  mutable_parameter_block_sizes()->assign({4, 3, 3});
  if (uses_scale_) mutable_parameter_block_sizes()->push_back(1);
}

bool VehicleVelocityFactor::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> v(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> bg(parameters[2]);
  const double s = uses_scale_ ? parameters[3][0] : 0.0;
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Vector3d v_b = R.transpose() * v;
  const Eigen::Vector3d w_ie_b = R.transpose() * omega_ie_w_;
  const Eigen::Vector3d omega_wb = obs_.omega_raw_b - bg - w_ie_b;
  const Eigen::Vector3d v_v = C_vb_ * (v_b + omega_wb.cross(lever_b_));
  const Eigen::Matrix3d L = skew(lever_b_);
  Eigen::Matrix3d J_d = C_vb_ * (skew(v_b) + L * skew(w_ie_b));
  Eigen::Matrix3d J_v = C_vb_ * R.transpose();
  Eigen::Matrix3d J_bg = C_vb_ * L;
  const int m = num_residuals();
  for (int i = 0; i < m; ++i) {
    const int row = rows_[i];
    const double w = 1.0 / obs_.row_std_m_s(row);
    double gain = 1.0, r = v_v(row);
    if (row == 0) {
      gain = 1.0 + s;
      r = gain * v_v.x() - obs_.speed_m_s;
    }
    residuals[i] = w * r;
    if (jacobians == nullptr) continue;
    if (jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 1, 4>> Jq(jacobians[0] + 4 * i);
      Jq = (w * gain * J_d.row(row)) * tangentToAmbientJacobian(q);
    }
    if (jacobians[1])
      Eigen::Map<Eigen::RowVector3d>(jacobians[1] + 3 * i) = w * gain * J_v.row(row);
    if (jacobians[2])
      Eigen::Map<Eigen::RowVector3d>(jacobians[2] + 3 * i) = w * gain * J_bg.row(row);
    if (uses_scale_ && jacobians[3]) jacobians[3][i] = row == 0 ? w * v_v.x() : 0.0;
  }
  return true;
}

}  // namespace graftnav
