#include "graftnav/filters/vehicle_velocity.h"

#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

using namespace ekf;

namespace {
Eigen::Vector3d omegaIn(const NavState& s) {
  return earth::omega_ie_n(s.pos.lat_rad) + earth::omega_en_n(s.pos, s.v_n);
}
}  // namespace

Eigen::Vector3d vehicleVelocity(const NavState& s, const Eigen::Vector3d& omega_ib_b,
                                const VehicleGeometry& g) {
  const Eigen::Matrix3d C_bn = s.q_nb.toRotationMatrix().transpose();
  const Eigen::Vector3d omega_nb_b = omega_ib_b - C_bn * omegaIn(s);
  return g.C_vb * (C_bn * s.v_n + omega_nb_b.cross(g.lever_arm_b_m));
}

Eigen::Matrix<double, 3, kStateDim> vehicleVelocityJacobian(const NavState& s,
                                                            const Eigen::Vector3d& omega_ib_b,
                                                            const VehicleGeometry& g) {
  Eigen::Matrix<double, 3, kStateDim> H = Eigen::Matrix<double, 3, kStateDim>::Zero();
  const Eigen::Matrix3d C_bn = s.q_nb.toRotationMatrix().transpose();
  const Eigen::Matrix3d L = skew(g.lever_arm_b_m);
  const Eigen::Matrix3d lever_turn = -g.C_vb * L * C_bn * skew(omegaIn(s));  // per (psi + T dr)
  H.block<3, 3>(0, kPos) = lever_turn * frameRotationPerPosition(s.pos);
  H.block<3, 3>(0, kVel) = g.C_vb * C_bn;
  H.block<3, 3>(0, kAtt) = -g.C_vb * C_bn * skew(s.v_n) + lever_turn;
  H.block<3, 3>(0, kGyroBias) = -g.C_vb * L;
  H.block<3, 3>(0, kGyroScale) = -g.C_vb * L * omega_ib_b.asDiagonal();
  return H;
}

}  // namespace graftnav
