#pragma once
// Odometer and NHC factor on one node (model and frames: graftnav/estimation/vehicle_aiding.h),
// the EKF's vehicle-frame velocity update as a factor. In the Earth-fixed frame w of the nodes:
//
//   v_v = C_vb (R_wb^T v_w + omega_wb_b x l_b),   omega_wb_b = omega_raw_b - bg - R_wb^T omega_ie_w
//
// with omega_raw_b the raw rate of the IMU sample that ends at the node. Residual rows, each
// divided by its 1-sigma: forward (1 + s) v_v.x - speed (with an odometer speed at the node),
// lateral v_v.y and vertical v_v.z (NHC, or the odometer's own lateral/vertical std).
// Parameter blocks: q_wb[4], v_w[3], bg[3], and s[1] (the node's odometer scale factor) when the
// scale is estimated and the forward row is there. Jacobians for the right perturbation
// R Exp(d): d(R^T x)/dd = [R^T x]x, so
//   dv_v/dd = C_vb ([R^T v]x + [l]x [R^T omega_ie]x),  dv_v/dv = C_vb R^T,  dv_v/dbg = C_vb [l]x.
// Checked against numeric Jacobians in graph/tests.

#include <ceres/cost_function.h>

#include <Eigen/Core>

namespace graftnav {

struct VehicleObservation {
  Eigen::Vector3d omega_raw_b = Eigen::Vector3d::Zero();  // rad/s, the sample ending at the node
  bool has_speed = false;                                 // an odometer speed at the node
  double speed_m_s = 0.0;
  // 1-sigma of the rows forward (used only with a speed), lateral, vertical; <= 0: no row.
  Eigen::Vector3d row_std_m_s = Eigen::Vector3d::Zero();
  int rows() const;  // rows the factor will have
};

class VehicleVelocityFactor final : public ceres::CostFunction {
 public:
  // with_scale: the forward row carries the node's scale block (when it has a forward row).
  VehicleVelocityFactor(const VehicleObservation& obs, const Eigen::Matrix3d& C_vb,
                        const Eigen::Vector3d& lever_arm_b_m, const Eigen::Vector3d& omega_ie_w,
                        bool with_scale);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;
  // Whether the factor has the scale block (the fourth).
  bool usesScale() const { return uses_scale_; }

 private:
  VehicleObservation obs_;
  Eigen::Matrix3d C_vb_;
  Eigen::Vector3d lever_b_, omega_ie_w_;
  bool uses_scale_;
  int rows_[3] = {0, 0, 0};
};

}  // namespace graftnav
