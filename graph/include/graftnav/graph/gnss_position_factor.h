#pragma once
// GNSS antenna position factor on one node (docs/fgo.md, section 3).
//   r = S (p_w + R_wb l_b + v_w dt - z_w)
// l_b the antenna lever arm (body FRD), dt = t_fix - t_node (the node sits on the IMU sample
// nearest the fix, |dt| <= half a sample, or on a node shared with a fix less than two samples
// away, |dt| < two samples: graph/node_layout.h), z_w the fix in the local frame, S the square root of
// the fix's information rotated into w. Blocks: p_w[3], q_wb[4], v_w[3]. Robust loss and
// chi-square culling are applied by the solver.

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

namespace graftnav {

class GnssPositionFactor final : public ceres::SizedCostFunction<3, 3, 4, 3> {
 public:
  GnssPositionFactor(const Eigen::Vector3d& z_w, const Eigen::Matrix3d& sqrt_info_w,
                     const Eigen::Vector3d& lever_arm_b, double dt_s);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Vector3d z_w_;
  Eigen::Matrix3d sqrt_info_;
  Eigen::Vector3d lever_b_;
  double dt_s_;
};

}  // namespace graftnav
