#pragma once
// Rotation conventions of graftnav, stated once for the whole project.
//
// Frames: body b = forward-right-down (FRD); navigation n = north-east-down (NED), the local-level
// frame at the current position; Earth e (ECEF); inertial i.
//
// C_ab is the direction cosine matrix that maps a vector resolved in frame b to frame a:
//   v_a = C_ab * v_b.  So C_nb maps body vectors into NED.
// q_ab is the Hamilton unit quaternion of the same rotation (Eigen::Quaterniond, w first in
// storage order of the constructor, active rotation): v_a = q_ab * v_b, and
// q_ac = q_ab * q_bc.
// Euler angles are the aerospace ZYX sequence of b relative to n: yaw psi about z (down), then
// pitch theta about the new y, then roll phi about the new x:
//   C_nb = Rz(psi) * Ry(theta) * Rx(phi)   (seed Eq. 15).
// They are stored as Eigen::Vector3d euler_rad = [roll, pitch, yaw] in radians.
// A rotation vector rv (axis times angle, rad) gives q = exp(rv) = [cos(|rv|/2), sin(|rv|/2) rv/|rv|].
// Angular rates omega_ab_c are the rate of frame b relative to frame a, resolved in frame c.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace graftnav {

// Cross-product (skew-symmetric) matrix: skew(a) * b == a.cross(b).
Eigen::Matrix3d skew(const Eigen::Vector3d& v);

// q = exp(rv); exact, and stable near zero through a Taylor series of sin(x/2)/x.
Eigen::Quaterniond quatFromRotationVector(const Eigen::Vector3d& rv_rad);

// The inverse of quatFromRotationVector, |angle| <= pi; stable near zero and near pi.
Eigen::Vector3d rotationVectorFromQuat(const Eigen::Quaterniond& q);

// C = exp(skew(rv)) (Rodrigues), stable near zero.
Eigen::Matrix3d dcmFromRotationVector(const Eigen::Vector3d& rv_rad);

// ZYX Euler [roll, pitch, yaw] (rad) <-> C_nb / q_nb.
Eigen::Matrix3d dcmFromEuler(const Eigen::Vector3d& euler_rad);
Eigen::Quaterniond quatFromEuler(const Eigen::Vector3d& euler_rad);
// Yaw is returned in (-pi, pi]; at pitch = +-90 deg roll is set to 0 and yaw carries the rest.
Eigen::Vector3d eulerFromDcm(const Eigen::Matrix3d& C_nb);
Eigen::Vector3d eulerFromQuat(const Eigen::Quaterniond& q_nb);

// Roll and pitch from a mean specific force in body axes (at rest f_b = C_bn [0, 0, -g]).
Eigen::Vector2d levelFromSpecificForce(const Eigen::Vector3d& f_b);

// Wraps an angle to (-pi, pi].
double wrapAngle(double angle_rad);

// Right Jacobian of SO(3), Jr(phi), and its inverse: exp(phi + dphi) ~= exp(phi) exp(Jr(phi) dphi).
Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi_rad);
Eigen::Matrix3d rightJacobianInverseSO3(const Eigen::Vector3d& phi_rad);

constexpr double kDegToRad = 0.017453292519943295769;
constexpr double kRadToDeg = 57.295779513082320877;

}  // namespace graftnav
