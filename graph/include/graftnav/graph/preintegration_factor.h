#pragma once
// IMU preintegration factor between nodes i and j in the Earth-fixed local frame w
// (graph/local_frame.h), with the Earth rotation kept in the residual (docs/fgo.md, section 2).
//
// Parameter blocks: p_i[3], q_wb_i[4], v_i[3], bg_i[3], ba_i[3], p_j[3], q_wb_j[4], v_j[3]
// (quaternions on RightQuaternionManifold), and sg_i[3], sa_i[3] when the preintegration carries
// scale factors (ImuPreintegration::withScale(): the increments then first order in them too). With R = C_wb, T = t_j - t_i, W = [omega_ie_w]x,
// g = gravity at the mid-point (p_i + p_j)/2 (g_p at (2 p_i + p_j)/3 for position), A = R_i^T omega_ie_w, and the bias-corrected
// increments ^dR, ^dv, ^dp of ImuPreintegration:
//   r_p   = R_i^T (p_j - p_i - v_i T - 1/2 g_p T^2 + W T^2 (2 v_i + v_j)/3) + A x c  - ^dp
//   r_v   = R_i^T (v_j - v_i - g T + 2 W (p_j - p_i))                     + A x m1 - ^dv
//   r_phi = Log(^dR^T R_i^T Exp(omega_ie_w T) R_j)
// whitened by the preintegration's square-root information. With earth_rotation = false,
// omega_ie_w is taken as zero (gravity stays), which is the uncompensated preintegration.
// Analytic Jacobians (docs/fgo.md), checked against numeric ones in graph/tests.

#include <ceres/cost_function.h>

#include "graftnav/graph/imu_preintegration.h"
#include "graftnav/graph/local_frame.h"

namespace graftnav {

class PreintegrationFactor final : public ceres::CostFunction {
 public:
  // `pre` must outlive the factor; it may be re-integrated between solves (not during one), with
  // scale factors or without as when the factor was made.
  PreintegrationFactor(const ImuPreintegration* pre, const Eigen::Vector3d& omega_ie_w,
                       const LinearGravity& gravity);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Refreshes the cached square-root information after `pre` was re-integrated.
  void refresh() { sqrt_info_ = pre_->sqrtInformation(); }

  // Node j predicted from node i by setting the residual to zero (used to initialize nodes).
  void predict(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
               const Eigen::Vector3d& v_i, const Eigen::Vector3d& bg_i, const Eigen::Vector3d& ba_i,
               Eigen::Vector3d* p_j, Eigen::Quaterniond* q_j, Eigen::Vector3d* v_j) const;
  // The same with node i's scale factors (withScale() preintegrations).
  void predict(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
               const Eigen::Vector3d& v_i, const Eigen::Vector3d& bg_i, const Eigen::Vector3d& ba_i,
               const ImuScaleFactors& s_i, Eigen::Vector3d* p_j, Eigen::Quaterniond* q_j,
               Eigen::Vector3d* v_j) const;
  bool usesScale() const { return with_scale_; }

  const ImuPreintegration& preintegration() const { return *pre_; }

 private:
  // Node i's corrected increments and the rotation correction phi_b (at pre's linearization
  // scales when the factor carries none).
  void corrected(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba, const double* sg,
                 const double* sa, Eigen::Vector3d* phi_b, Eigen::Vector3d* dv_hat,
                 Eigen::Vector3d* dp_hat) const;

  const ImuPreintegration* pre_;
  bool with_scale_;
  Eigen::Vector3d omega_ie_w_;
  LinearGravity gravity_;
  ImuPreintegration::Matrix9d sqrt_info_;
};

}  // namespace graftnav
