#pragma once
// The vehicle-frame velocity of the odometer point as the EKF sees it, and its Jacobian with
// respect to the 21-state error of ins_error_model.h (model and frames:
// graftnav/estimation/vehicle_aiding.h):
//
//   v_v = C_vb (C_bn v_n + omega_nb_b x l_b),   omega_nb_b = omega_ib_b - C_bn omega_in_n
//
// With the error conventions of ins_error_model.h (dv, psi computed minus true; dbg, dsg the
// error left in the corrected gyro output, omega_c = omega + dbg + diag(omega) dsg), to first
// order:
//   dv_v = C_vb [ C_bn dv - C_bn [v_n x] psi - [l x] (dbg + diag(omega_ib_b) dsg)
//                 - [l x] C_bn [omega_in_n x] (psi + T dr) ]
// (T of frameRotationPerPosition: the position error turns the computed n frame). The dr terms
// of C_bn v_n cancel in the psi-angle form. The odometer's row is (1 + k) times the forward row,
// with -v_v.x for its scale state (true minus estimated, like the sensor states).

#include <Eigen/Core>

#include "graftnav/filters/ins_error_model.h"

namespace graftnav {

struct VehicleGeometry {
  Eigen::Matrix3d C_vb = Eigen::Matrix3d::Identity();       // IMU body to vehicle
  Eigen::Vector3d lever_arm_b_m = Eigen::Vector3d::Zero();  // odometer point from the IMU, FRD
};

// v_v at the computed state with the corrected body rate omega_ib_b (rad/s).
Eigen::Vector3d vehicleVelocity(const NavState& s, const Eigen::Vector3d& omega_ib_b,
                                const VehicleGeometry& g);

// d(v_v)/d(error state), rows forward, lateral, vertical (dr, dv, psi, dbg, dsg blocks).
Eigen::Matrix<double, 3, ekf::kStateDim> vehicleVelocityJacobian(const NavState& s,
                                                                 const Eigen::Vector3d& omega_ib_b,
                                                                 const VehicleGeometry& g);

}  // namespace graftnav
