#pragma once
// Unit-quaternion manifold with a RIGHT (body-frame) perturbation, for attitude nodes q_wb.
//
// Ambient: Eigen::Quaterniond storage order (x, y, z, w). Tangent: a rotation vector delta (rad,
// full angle, body frame):
//   Plus(q, delta)  = q * Exp(delta),          Exp(d) = [cos(|d|/2), sin(|d|/2) d/|d|]
//   Minus(y, x)     = 2 atan2(|v|, w) v/|v|,   [w, v] = x^-1 * y   (exact inverse of Plus; no
//                     shortest-path flip, so Plus(x, Minus(y, x)) == y holds as vectors)
// Ceres' own EigenQuaternionManifold perturbs on the left (Exp(delta) * q); the factors of graph/
// derive their Jacobians for the right perturbation, so they need this manifold.
//
// PlusJacobian at delta = 0 (4x3, row-major, rows x,y,z,w):  P = 1/2 [w I + [v]x ; -v^T]
// MinusJacobian at y = x    (3x4):                            P+ = 2 [w I - [v]x , -v]
// P+ P = I for a unit quaternion. A cost function that has its Jacobian J_t with respect to the
// tangent writes the ambient Jacobian J_t * P+ (ambientFromTangentJacobian), so that Ceres'
// J_ambient * P recovers J_t exactly.

#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace graftnav {

class RightQuaternionManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 4; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// P+ of the header comment: maps a tangent-space Jacobian (N x 3) to the ambient one (N x 4).
Eigen::Matrix<double, 3, 4> tangentToAmbientJacobian(const Eigen::Quaterniond& q);

}  // namespace graftnav
