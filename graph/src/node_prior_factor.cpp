#include "graftnav/graph/node_prior_factor.h"

#include <stdexcept>
#include <string>

#include "graftnav/nav/rotation.h"
#include "graftnav/graph/right_quaternion_manifold.h"

namespace graftnav {

NodePriorFactor::NodePriorFactor(const NodeValue& x0, const Matrix15d& S, const Vector15d& e)
    : x0_(x0), S_(S), e_(e) {}

Eigen::Matrix<double, 15, 1> nodeDifference(const NodeValue& x0, double const* const* parameters,
                                            Eigen::Vector3d* dth) {
  const Eigen::Map<const Eigen::Vector3d> p(parameters[0]);
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> v(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> bg(parameters[3]);
  const Eigen::Map<const Eigen::Vector3d> ba(parameters[4]);
  Eigen::Matrix<double, 15, 1> dx;
  dx.segment<3>(0) = p - x0.p_w;
  *dth = rotationVectorFromQuat(x0.q_wb.conjugate() * q);
  dx.segment<3>(3) = *dth;
  dx.segment<3>(6) = v - x0.v_w;
  dx.segment<3>(9) = bg - x0.bg;
  dx.segment<3>(12) = ba - x0.ba;
  return dx;
}

bool NodePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[1]);
  Eigen::Vector3d dth;
  const Vector15d dx = nodeDifference(x0_, parameters, &dth);
  Eigen::Map<Vector15d>{residuals} = S_.lazyProduct(dx) + e_;
  if (jacobians == nullptr) return true;
  using Mat153R = Eigen::Matrix<double, 15, 3, Eigen::RowMajor>;
  using Mat154R = Eigen::Matrix<double, 15, 4, Eigen::RowMajor>;
  for (int b : {0, 2, 3, 4}) {
    if (!jacobians[b]) continue;
    const int col = 3 * b;  // tangent columns: p 0, q 3, v 6, bg 9, ba 12
    Eigen::Map<Mat153R>{jacobians[b]} = S_.middleCols<3>(col);
  }
  if (jacobians[1]) {
    // Log(q0^-1 q Exp(d)) ~= dth + Jr^-1(dth) d.
    const Eigen::Matrix<double, 15, 3> J_t =
        S_.middleCols<3>(3).lazyProduct(rightJacobianInverseSO3(dth));
    Eigen::Map<Mat154R>{jacobians[1]} = J_t * tangentToAmbientJacobian(q);
  }
  return true;
}

NodeScalePriorFactor::NodeScalePriorFactor(const NodeValue& x0, const Matrix16d& S,
                                           const Vector16d& e)
    : x0_(x0), S_(S), e_(e) {}

bool NodeScalePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[1]);
  Eigen::Vector3d dth;
  Vector16d dx;
  dx.head<15>() = nodeDifference(x0_, parameters, &dth);
  dx(15) = parameters[5][0] - x0_.odometer_scale;
  Eigen::Map<Vector16d>{residuals} = S_.lazyProduct(dx) + e_;
  if (jacobians == nullptr) return true;
  using Mat163R = Eigen::Matrix<double, 16, 3, Eigen::RowMajor>;
  using Mat164R = Eigen::Matrix<double, 16, 4, Eigen::RowMajor>;
  for (int b : {0, 2, 3, 4}) {
    if (jacobians[b]) Eigen::Map<Mat163R>{jacobians[b]} = S_.middleCols<3>(3 * b);
  }
  if (jacobians[1]) {
    const Eigen::Matrix<double, 16, 3> J_t =
        S_.middleCols<3>(3).lazyProduct(rightJacobianInverseSO3(dth));
    Eigen::Map<Mat164R>{jacobians[1]} = J_t * tangentToAmbientJacobian(q);
  }
  if (jacobians[5]) Eigen::Map<Vector16d>{jacobians[5]} = S_.col(15);
  return true;
}

NodeImuScalePriorFactor::NodeImuScalePriorFactor(const NodeValue& x0, const Eigen::MatrixXd& S,
                                                 const Eigen::VectorXd& e, bool odometer_scale)
    : x0_(x0), S_(S), e_(e), odometer_scale_(odometer_scale) {
  const int n = odometer_scale ? 22 : 21;
  if (S.rows() != n || S.cols() != n || e.size() != n) {
    throw std::invalid_argument("NodeImuScalePriorFactor: S and e must have " + std::to_string(n) +
                                " rows");
  }
  set_num_residuals(n);
  *mutable_parameter_block_sizes() = {3, 4, 3, 3, 3, 3, 3};
  if (odometer_scale) mutable_parameter_block_sizes()->push_back(1);
}

bool NodeImuScalePriorFactor::Evaluate(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int n = static_cast<int>(e_.size());
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[1]);
  Eigen::Vector3d dth;
  Eigen::VectorXd dx(n);
  dx.head<15>() = nodeDifference(x0_, parameters, &dth);
  dx.segment<3>(15) = Eigen::Map<const Eigen::Vector3d>(parameters[5]) - x0_.imu_scale.gyro;
  dx.segment<3>(18) = Eigen::Map<const Eigen::Vector3d>(parameters[6]) - x0_.imu_scale.accel;
  if (odometer_scale_) dx(21) = parameters[7][0] - x0_.odometer_scale;
  Eigen::Map<Eigen::VectorXd>(residuals, n) = S_ * dx + e_;
  if (jacobians == nullptr) return true;
  const int cols[8] = {0, 3, 6, 9, 12, 15, 18, 21};  // tangent column of each block
  for (int b = 0; b < (odometer_scale_ ? 8 : 7); ++b) {
    if (!jacobians[b] || b == 1) continue;
    const int w = b == 7 ? 1 : 3;
    Eigen::Map<RowMajor>(jacobians[b], n, w) = S_.middleCols(cols[b], w);
  }
  if (jacobians[1]) {
    const Eigen::MatrixXd J_t = S_.middleCols<3>(3) * rightJacobianInverseSO3(dth);
    Eigen::Map<RowMajor>(jacobians[1], n, 4) = J_t * tangentToAmbientJacobian(q);
  }
  return true;
}

}  // namespace graftnav
