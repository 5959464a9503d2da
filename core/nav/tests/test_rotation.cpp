#include <gtest/gtest.h>

#include <random>

#include "graftnav/nav/rotation.h"
#include "test_support.h"

namespace graftnav {
namespace {

TEST(Rotation, EulerRoundTripAndConvention) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d e(M_PI * u(rng), 0.499 * M_PI * u(rng), M_PI * u(rng));
    const Eigen::Vector3d back = eulerFromDcm(dcmFromEuler(e));
    EXPECT_NEAR(wrapAngle(back.x() - e.x()), 0.0, 1e-9);
    EXPECT_NEAR(back.y() - e.y(), 0.0, 1e-9);
    EXPECT_NEAR(wrapAngle(back.z() - e.z()), 0.0, 1e-9);
  }
  // Seed Eq. 15, element by element, for one attitude.
  const double r = 0.1, p = -0.2, y = 2.5;
  const Eigen::Matrix3d C = dcmFromEuler({r, p, y});
  EXPECT_NEAR(C(0, 0), std::cos(p) * std::cos(y), 1e-15);
  EXPECT_NEAR(C(0, 1), -std::cos(r) * std::sin(y) + std::sin(r) * std::sin(p) * std::cos(y), 1e-15);
  EXPECT_NEAR(C(1, 2), -std::sin(r) * std::cos(y) + std::cos(r) * std::sin(p) * std::sin(y), 1e-15);
  EXPECT_NEAR(C(2, 0), -std::sin(p), 1e-15);
  EXPECT_NEAR(C(2, 1), std::sin(r) * std::cos(p), 1e-15);
  // A yaw of +90 deg maps body forward to east.
  const Eigen::Vector3d fwd_n = dcmFromEuler({0, 0, M_PI / 2}) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(fwd_n.y(), 1.0, 1e-15);
}

TEST(Rotation, RotationVectorRoundTripNearZeroAndPi) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double scale : {1e-12, 1e-9, 1e-6, 1e-3, 0.5, 3.0, M_PI - 1e-7}) {
    for (int i = 0; i < 200; ++i) {
      Eigen::Vector3d rv(n(rng), n(rng), n(rng));
      rv = rv.normalized() * scale;
      const Eigen::Quaterniond q = quatFromRotationVector(rv);
      EXPECT_NEAR(q.norm(), 1.0, 1e-15);
      const Eigen::Vector3d back = rotationVectorFromQuat(q);
      EXPECT_LT((back - rv).norm(), 1e-12 * std::max(1.0, scale)) << "scale " << scale;
      // Against Eigen's AngleAxis away from zero.
      if (scale > 1e-6) {
        const Eigen::Matrix3d R = Eigen::AngleAxisd(rv.norm(), rv.normalized()).toRotationMatrix();
        EXPECT_LT((q.toRotationMatrix() - R).norm(), 1e-13);
      }
    }
  }
}

TEST(Rotation, RightJacobianMatchesNumeric) {
  for (const Eigen::Vector3d& phi :
       {Eigen::Vector3d(0.3, -0.2, 0.9), Eigen::Vector3d(1e-7, 0, 2e-7),
        Eigen::Vector3d(2.0, 1.0, -0.5)}) {
    // exp(phi + d) = exp(phi) exp(Jr d)  =>  log(exp(phi)^-1 exp(phi + d)) / d = Jr.
    const Eigen::Quaterniond q0 = quatFromRotationVector(phi);
    auto f = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return rotationVectorFromQuat(q0.conjugate() * quatFromRotationVector(phi + d));
    };
    const Eigen::MatrixXd J = test::numericJacobian(f, Eigen::Vector3d::Zero(), 1e-6);
    EXPECT_LT((J - rightJacobianSO3(phi)).norm(), 1e-8);
    EXPECT_LT(
        (rightJacobianInverseSO3(phi) * rightJacobianSO3(phi) - Eigen::Matrix3d::Identity()).norm(),
        1e-10);
  }
}

}  // namespace
}  // namespace graftnav
