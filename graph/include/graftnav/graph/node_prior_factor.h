#pragma once
// Linear(ized) prior on one node's full state x = (p_w, q_wb, v_w, bg, ba), 15 tangent dims:
//   r = S (x [-] x0) + e,   x [-] x0 = (p - p0, Log(q0^-1 q), v - v0, bg - bg0, ba - ba0)
// Used twice: as the prior on the first node (S = diag(1/sigma), e = 0), and as the
// marginalization prior of the sliding window (S, e from the Schur complement; docs/fgo.md).
// Blocks: p[3], q[4], v[3], bg[3], ba[3]. Tangent order of S's columns: the same.

#include <ceres/cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "graftnav/graph/imu_preintegration.h"

namespace graftnav {

struct NodeValue {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_wb = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();
  Eigen::Vector3d ba = Eigen::Vector3d::Zero();
  double odometer_scale = 0.0;  // used only when the graph estimates it (vehicle_aiding.h)
  ImuScaleFactors imu_scale;    // used only when the graph estimates them (FgoOptions)
};

// x [-] x0 over the five blocks at `parameters` (p, q, v, bg, ba), and Log(q0^-1 q) (the q
// columns' Jacobian is then Jr^-1 of it).
Eigen::Matrix<double, 15, 1> nodeDifference(const NodeValue& x0, double const* const* parameters,
                                            Eigen::Vector3d* dth);

class NodePriorFactor final : public ceres::SizedCostFunction<15, 3, 4, 3, 3, 3> {
 public:
  using Matrix15d = Eigen::Matrix<double, 15, 15>;
  using Vector15d = Eigen::Matrix<double, 15, 1>;
  NodePriorFactor(const NodeValue& x0, const Matrix15d& S, const Vector15d& e);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  NodeValue x0_;
  Matrix15d S_;
  Vector15d e_;
};

// The same on a node with its odometer scale s (16 tangent dims, s last): the sliding window's
// marginalization prior when the graph estimates the scale. Blocks: p, q, v, bg, ba, s[1].
class NodeScalePriorFactor final : public ceres::SizedCostFunction<16, 3, 4, 3, 3, 3, 1> {
 public:
  using Matrix16d = Eigen::Matrix<double, 16, 16>;
  using Vector16d = Eigen::Matrix<double, 16, 1>;
  NodeScalePriorFactor(const NodeValue& x0, const Matrix16d& S, const Vector16d& e);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  NodeValue x0_;
  Matrix16d S_;
  Vector16d e_;
};

// The same on a node with its IMU scale factors sg, sa (21 tangent dims) and, with
// `odometer_scale`, s (22): the sliding window's marginalization prior when the graph estimates
// the IMU scale factors. Blocks: p, q, v, bg, ba, sg[3], sa[3] (, s[1]); S's columns the same.
class NodeImuScalePriorFactor final : public ceres::CostFunction {
 public:
  NodeImuScalePriorFactor(const NodeValue& x0, const Eigen::MatrixXd& S, const Eigen::VectorXd& e,
                          bool odometer_scale);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  NodeValue x0_;
  Eigen::MatrixXd S_;
  Eigen::VectorXd e_;
  bool odometer_scale_;
};

}  // namespace graftnav
