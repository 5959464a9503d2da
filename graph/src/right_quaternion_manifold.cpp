#include "graftnav/graph/right_quaternion_manifold.h"

#include <cmath>

#include "graftnav/nav/rotation.h"

namespace graftnav {

bool RightQuaternionManifold::Plus(const double* x, const double* delta,
                                   double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x);
  const Eigen::Map<const Eigen::Vector3d> d(delta);
  Eigen::Map<Eigen::Quaterniond> out(x_plus_delta);
  out = q * quatFromRotationVector(d);
  return true;
}

bool RightQuaternionManifold::PlusJacobian(const double* x, double* jacobian) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x);
  Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>> P(jacobian);
  P.topRows<3>() = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + skew(q.vec()));
  P.bottomRows<1>() = -0.5 * q.vec().transpose();
  return true;
}

bool RightQuaternionManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Map<const Eigen::Quaterniond> qy(y);
  const Eigen::Map<const Eigen::Quaterniond> qx(x);
  // x is on the manifold (unit); y may be perturbed off it by numeric differentiation, and the
  // atan2 form below is invariant to the scale of y.
  const Eigen::Quaterniond d = qx.conjugate() * qy;
  const double s = d.vec().norm();
  Eigen::Map<Eigen::Vector3d> out(y_minus_x);
  if (s < 1e-10) {
    out = (2.0 / d.w()) * d.vec();
  } else {
    out = (2.0 * std::atan2(s, d.w()) / s) * d.vec();
  }
  return true;
}

bool RightQuaternionManifold::MinusJacobian(const double* x, double* jacobian) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x);
  Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> J(jacobian);
  J = tangentToAmbientJacobian(q);
  return true;
}

Eigen::Matrix<double, 3, 4> tangentToAmbientJacobian(const Eigen::Quaterniond& q) {
  Eigen::Matrix<double, 3, 4> J;
  J.leftCols<3>() = 2.0 * (q.w() * Eigen::Matrix3d::Identity() - skew(q.vec()));
  J.rightCols<1>() = -2.0 * q.vec();
  return J;
}

}  // namespace graftnav
