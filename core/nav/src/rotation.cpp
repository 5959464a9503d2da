#include "graftnav/nav/rotation.h"

#include <cmath>

namespace graftnav {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Quaterniond quatFromRotationVector(const Eigen::Vector3d& rv_rad) {
  const double theta2 = rv_rad.squaredNorm();
  double w, k;  // q = [w, k * rv]
  if (theta2 < 1e-12) {
    // cos(x/2) and sin(x/2)/x to fourth order; exact to double precision here.
    w = 1.0 - theta2 / 8.0 + theta2 * theta2 / 384.0;
    k = 0.5 - theta2 / 48.0 + theta2 * theta2 / 3840.0;
  } else {
    const double theta = std::sqrt(theta2);
    w = std::cos(0.5 * theta);
    k = std::sin(0.5 * theta) / theta;
  }
  Eigen::Quaterniond q(w, k * rv_rad.x(), k * rv_rad.y(), k * rv_rad.z());
  return q;
}

Eigen::Vector3d rotationVectorFromQuat(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // shortest rotation, angle in [0, pi]
  const double s = q.vec().norm();
  if (s < 1e-8) {
    // angle = 2 atan2(s, w) ~ 2 s / w (1 - s^2/(3 w^2)); scale = angle / s.
    const double w = q.w();
    return (2.0 / w) * (1.0 - s * s / (3.0 * w * w)) * q.vec();
  }
  const double angle = 2.0 * std::atan2(s, q.w());
  return (angle / s) * q.vec();
}

Eigen::Matrix3d dcmFromRotationVector(const Eigen::Vector3d& rv_rad) {
  return quatFromRotationVector(rv_rad).toRotationMatrix();
}

Eigen::Matrix3d dcmFromEuler(const Eigen::Vector3d& e) {
  return quatFromEuler(e).toRotationMatrix();
}

Eigen::Quaterniond quatFromEuler(const Eigen::Vector3d& e) {
  const Eigen::Quaterniond qz(Eigen::AngleAxisd(e.z(), Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond qy(Eigen::AngleAxisd(e.y(), Eigen::Vector3d::UnitY()));
  const Eigen::Quaterniond qx(Eigen::AngleAxisd(e.x(), Eigen::Vector3d::UnitX()));
  return (qz * qy * qx).normalized();
}

Eigen::Vector3d eulerFromDcm(const Eigen::Matrix3d& C) {
  // C(2,0) = -sin(pitch); C(2,1) = sin(roll) cos(pitch); C(2,2) = cos(roll) cos(pitch);
  // C(1,0) = cos(pitch) sin(yaw); C(0,0) = cos(pitch) cos(yaw).
  const double s_pitch = -C(2, 0);
  Eigen::Vector3d e;
  if (std::abs(s_pitch) > 1.0 - 1e-12) {
    e.y() = std::copysign(0.5 * M_PI, s_pitch);
    e.x() = 0.0;
    e.z() = std::atan2(-C(0, 1), C(1, 1));
  } else {
    e.y() = std::atan2(s_pitch, std::hypot(C(2, 1), C(2, 2)));
    e.x() = std::atan2(C(2, 1), C(2, 2));
    e.z() = std::atan2(C(1, 0), C(0, 0));
  }
  return e;
}

Eigen::Vector3d eulerFromQuat(const Eigen::Quaterniond& q_nb) {
  return eulerFromDcm(q_nb.toRotationMatrix());
}

Eigen::Vector2d levelFromSpecificForce(const Eigen::Vector3d& f) {
  return {std::atan2(-f.y(), -f.z()), std::atan2(f.x(), std::hypot(f.y(), f.z()))};
}

double wrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);  // [-pi, pi]
  if (a <= -M_PI) a += 2.0 * M_PI;
  return a;
}

Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  const Eigen::Matrix3d K = skew(phi);
  if (t2 < 1e-10) return Eigen::Matrix3d::Identity() - 0.5 * K + K * K / 6.0;
  const double t = std::sqrt(t2);
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(t)) / t2 * K +
         (t - std::sin(t)) / (t2 * t) * K * K;
}

Eigen::Matrix3d rightJacobianInverseSO3(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  const Eigen::Matrix3d K = skew(phi);
  if (t2 < 1e-10) return Eigen::Matrix3d::Identity() + 0.5 * K + K * K / 12.0;
  const double t = std::sqrt(t2);
  return Eigen::Matrix3d::Identity() + 0.5 * K +
         (1.0 / t2 - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t))) * K * K;
}

}  // namespace graftnav
