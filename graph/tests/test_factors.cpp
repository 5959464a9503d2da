// Analytic Jacobians of every factor against numeric differentiation (ceres::GradientChecker and
// the suite's numericJacobian), and the manifold invariants of RightQuaternionManifold.
#include <ceres/gradient_checker.h>
#include <ceres/manifold_test_utils.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "graftnav/filters/vehicle_velocity.h"
#include "graftnav/graph/local_frame.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/graph/bias_factor.h"
#include "graftnav/graph/gnss_position_factor.h"
#include "graftnav/graph/imu_scale_prior_factor.h"
#include "graftnav/graph/node_prior_factor.h"
#include "graftnav/graph/odometer_scale_factor.h"
#include "graftnav/graph/preintegration_factor.h"
#include "graftnav/graph/right_quaternion_manifold.h"
#include "graftnav/graph/vehicle_velocity_factor.h"
#include "graph_scenario.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ceres::Vector;

Eigen::Quaterniond randomQuat(std::mt19937& rng, double max_angle) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Vector3d rv(u(rng), u(rng), u(rng));
  return quatFromRotationVector(rv.normalized() * max_angle * std::abs(u(rng)));
}

void expectJacobiansMatch(const ceres::CostFunction& cost, std::vector<double*> params,
                          const std::vector<const ceres::Manifold*>& manifolds, double precision) {
  ceres::NumericDiffOptions nd;
  ceres::GradientChecker checker(&cost, &manifolds, nd);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(params.data(), precision, &results);
  // GradientChecker's own verdict is entry-wise relative, which fails on entries that are zero
  // analytically and 1e-12 numerically; judge each block by its relative Frobenius error.
  ASSERT_EQ(results.local_jacobians.size(), params.size());
  for (size_t b = 0; b < params.size(); ++b) {
    const ceres::Matrix& J = results.local_jacobians[b];
    const ceres::Matrix& Jn = results.local_numeric_jacobians[b];
    const double scale = std::max(Jn.norm(), 1e-12);
    EXPECT_LT((J - Jn).norm() / scale, precision) << "block " << b << "\n" << results.error_log;
  }
}

void expectInvariants(const RightQuaternionManifold& manifold, const Vector& x, const Vector& delta,
                      const Vector& y) {
  using namespace ceres;  // NOLINT: the invariant macro names ceres' matchers unqualified
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, 1e-9);
}

TEST(RightQuaternionManifold, InvariantsHold) {
  RightQuaternionManifold manifold;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Quaterniond qx = randomQuat(rng, 3.0);
    Eigen::Quaterniond qy = qx * randomQuat(rng, 2.5);
    Vector x(4), y(4), delta(3);
    x << qx.x(), qx.y(), qx.z(), qx.w();
    y << qy.x(), qy.y(), qy.z(), qy.w();
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    delta << u(rng), u(rng), u(rng);
    expectInvariants(manifold, x, delta, y);
  }
  // Edge cases: identity, tiny and near-pi perturbations.
  Vector x(4), y(4), delta(3);
  x << 0, 0, 0, 1;
  y << 0, 0, std::sin(0.5 * 3.1), std::cos(0.5 * 3.1);
  delta << 1e-9, -2e-9, 3e-9;
  expectInvariants(manifold, x, delta, y);
}

TEST(RightQuaternionManifold, PlusIsRightMultiplication) {
  RightQuaternionManifold manifold;
  const Eigen::Quaterniond q = quatFromEuler(Eigen::Vector3d(0.1, -0.2, 2.0));
  const Eigen::Vector3d d(0.01, 0.02, -0.03);
  Eigen::Quaterniond out;
  manifold.Plus(q.coeffs().data(), d.data(), out.coeffs().data());
  EXPECT_LT((out.toRotationMatrix() - q.toRotationMatrix() * dcmFromRotationVector(d)).norm(),
            1e-14);
}

class FactorJacobians : public ::testing::Test {
 protected:
  void SetUp() override {
    sc_ = test::makeScenario(4.0, 200.0, 15.0);
    test::ImuErrors e;
    e.bg_rad_s << 2e-4, -1e-4, 3e-4;
    e.ba_m_s2 << 0.02, -0.03, 0.01;
    e.arw_rad_sqrt_s = 1e-4;
    e.vrw_m_s_sqrt_s = 1e-3;
    imu_ = test::addImuErrors(sc_.ideal, e, 3);
    frame_ = std::make_unique<LocalFrame>(sc_.truth.front().pos);
  }
  test::Scenario sc_;
  ImuSeries imu_;
  std::unique_ptr<LocalFrame> frame_;
  RightQuaternionManifold manifold_;
};

TEST_F(FactorJacobians, PreintegrationFactor) {
  std::mt19937 rng(11);
  std::normal_distribution<double> nd(0.0, 1.0);
  for (bool earth : {true, false}) {
    ImuPreintegration pre(Eigen::Vector3d(1e-4, 0, -1e-4), Eigen::Vector3d(0.01, 0, 0),
                          {1e-4, 1e-3});
    pre.reintegrate(imu_, 100, 300, Eigen::Vector3d(1e-4, 0, -1e-4), Eigen::Vector3d(0.01, 0, 0));
    Eigen::Vector3d p_i, v_i, p_j, v_j;
    Eigen::Quaterniond q_i, q_j;
    frame_->fromNavState(sc_.truth[100], &p_i, &v_i, &q_i);
    frame_->fromNavState(sc_.truth[300], &p_j, &v_j, &q_j);
    // Move away from the truth so that every residual term is non-zero.
    p_j += Eigen::Vector3d(nd(rng), nd(rng), nd(rng)) * 0.3;
    v_i += Eigen::Vector3d(nd(rng), nd(rng), nd(rng)) * 0.1;
    q_j = q_j * quatFromRotationVector(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)) * 0.01);
    q_i = q_i * quatFromRotationVector(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)) * 0.01);
    Eigen::Vector3d bg(3e-4, -2e-4, 1e-4), ba(0.03, -0.02, 0.05);
    const Eigen::Vector3d w = earth ? frame_->omega_ie_w() : Eigen::Vector3d::Zero().eval();
    PreintegrationFactor f(&pre, w, frame_->linearGravity(p_i));
    std::vector<double*> params = {p_i.data(),          q_i.coeffs().data(), v_i.data(),
                                   bg.data(),           ba.data(),           p_j.data(),
                                   q_j.coeffs().data(), v_j.data()};
    expectJacobiansMatch(
        f, params, {nullptr, &manifold_, nullptr, nullptr, nullptr, nullptr, &manifold_, nullptr},
        1e-5);

    // The same, in the tangent space, through the suite's numericJacobian helper (q_i block).
    auto residual_of_dtheta_i = [&](const Eigen::VectorXd& d) {
      Eigen::Quaterniond qp = q_i * quatFromRotationVector(d);
      std::vector<double*> pp = params;
      pp[1] = qp.coeffs().data();
      Eigen::Matrix<double, 9, 1> r;
      f.Evaluate(pp.data(), r.data(), nullptr);
      return Eigen::VectorXd(r);
    };
    const Eigen::MatrixXd J_num =
        test::numericJacobian(residual_of_dtheta_i, Eigen::VectorXd::Zero(3));
    Eigen::Matrix<double, 9, 4, Eigen::RowMajor> J_amb;
    std::vector<double*> jac(8, nullptr);
    jac[1] = J_amb.data();
    Eigen::Matrix<double, 9, 1> r;
    f.Evaluate(params.data(), r.data(), jac.data());
    Eigen::Matrix<double, 4, 3, Eigen::RowMajor> P;
    manifold_.PlusJacobian(q_i.coeffs().data(), P.data());
    const Eigen::MatrixXd J_tan = J_amb * P;
    EXPECT_LT((J_tan - J_num).norm(), 1e-6 * J_num.norm()) << J_tan << "\n\n" << J_num;
  }
}

TEST_F(FactorJacobians, PreintegrationFactorWithImuScaleFactors) {
  std::mt19937 rng(12);
  std::normal_distribution<double> nd(0.0, 1.0);
  const Eigen::Vector3d bg0(1e-4, 0, -1e-4), ba0(0.01, 0, 0);
  ImuScaleFactors s0;
  s0.gyro << 2e-3, -1e-3, 1e-3;
  s0.accel << 1e-3, 2e-3, -3e-3;
  ImuPreintegration pre(bg0, ba0, {1e-4, 1e-3});
  pre.reintegrate(imu_.data() + 100, 200, &imu_[99], bg0, ba0, s0);
  Eigen::Vector3d p_i, v_i, p_j, v_j;
  Eigen::Quaterniond q_i, q_j;
  frame_->fromNavState(sc_.truth[100], &p_i, &v_i, &q_i);
  frame_->fromNavState(sc_.truth[300], &p_j, &v_j, &q_j);
  p_j += Eigen::Vector3d(nd(rng), nd(rng), nd(rng)) * 0.3;
  q_j = q_j * quatFromRotationVector(Eigen::Vector3d(nd(rng), nd(rng), nd(rng)) * 0.01);
  Eigen::Vector3d bg(3e-4, -2e-4, 1e-4), ba(0.03, -0.02, 0.05);
  Eigen::Vector3d sg = s0.gyro + Eigen::Vector3d(5e-4, -5e-4, 1e-3);
  Eigen::Vector3d sa = s0.accel + Eigen::Vector3d(-1e-3, 5e-4, 5e-4);
  PreintegrationFactor f(&pre, frame_->omega_ie_w(), frame_->linearGravity(p_i));
  ASSERT_TRUE(f.usesScale());
  ASSERT_EQ(f.parameter_block_sizes().size(), 10u);
  std::vector<double*> params = {p_i.data(), q_i.coeffs().data(), v_i.data(), bg.data(), ba.data(),
                                 p_j.data(), q_j.coeffs().data(), v_j.data(), sg.data(), sa.data()};
  expectJacobiansMatch(f, params,
                       {nullptr, &manifold_, nullptr, nullptr, nullptr, nullptr, &manifold_,
                        nullptr, nullptr, nullptr},
                       1e-5);
}

TEST_F(FactorJacobians, ImuScaleFactorsPriorAndNodePrior) {
  const ImuScalePriorFactor prior(1e-3, 2e-3);
  Eigen::Vector3d sg(1e-3, -2e-3, 5e-4), sa(2e-3, 0.0, -4e-3);
  expectJacobiansMatch(prior, {sg.data(), sa.data()}, {nullptr, nullptr}, 1e-6);
  double r[6];
  const double* pa[] = {sg.data(), sa.data()};
  prior.Evaluate(pa, r, nullptr);
  EXPECT_NEAR(r[1], -2.0, 1e-12);
  EXPECT_NEAR(r[5], -2.0, 1e-12);

  std::mt19937 rng(7);
  NodeValue x0;
  x0.p_w << 1, 2, 3;
  x0.q_wb = randomQuat(rng, 2.0);
  x0.imu_scale.gyro << 1e-3, 0, 0;
  x0.odometer_scale = 1e-3;
  for (bool odo : {false, true}) {
    const int n = odo ? 22 : 21;
    const NodeImuScalePriorFactor f(x0, Eigen::MatrixXd::Random(n, n), Eigen::VectorXd::Random(n),
                                    odo);
    Eigen::Vector3d p(1.5, 2.2, 2.9), v(4.1, 4.9, 6.3), bg(1e-3, 0, 0), ba(0.1, 0.2, 0.0);
    double s = 2e-3;
    Eigen::Quaterniond q = x0.q_wb * quatFromRotationVector(Eigen::Vector3d(0.3, -0.2, 0.4));
    std::vector<double*> params = {p.data(),  q.coeffs().data(), v.data(), bg.data(),
                                   ba.data(), sg.data(),         sa.data()};
    std::vector<const ceres::Manifold*> m = {nullptr, &manifold_, nullptr, nullptr,
                                             nullptr, nullptr,    nullptr};
    if (odo) {
      params.push_back(&s);
      m.push_back(nullptr);
    }
    expectJacobiansMatch(f, params, m, 1e-6);
  }
}

TEST_F(FactorJacobians, GnssPositionFactor) {
  Eigen::Vector3d p(10.0, -20.0, 1.0), v(8.0, 3.0, -0.2);
  Eigen::Quaterniond q = quatFromEuler(Eigen::Vector3d(0.05, -0.03, 1.2));
  Eigen::Matrix3d S;
  S << 2.0, 0.1, 0.0, 0.0, 1.5, 0.2, 0.0, 0.0, 1.0;
  GnssPositionFactor f(Eigen::Vector3d(9.0, -19.0, 0.0), S, Eigen::Vector3d(0.3, -0.2, -1.2),
                       0.004);
  expectJacobiansMatch(f, {p.data(), q.coeffs().data(), v.data()}, {nullptr, &manifold_, nullptr},
                       1e-6);
}

TEST_F(FactorJacobians, BiasFactor) {
  BiasProcess gm{1e-4, 3600.0}, rw{2e-3, 0.0};
  BiasFactor f(gm, rw, 1.0);
  Eigen::Vector3d bgi(1e-4, 2e-4, -1e-4), bai(0.01, 0.02, 0.03), bgj(2e-4, 1e-4, 0.0),
      baj(0.02, 0.0, 0.01);
  expectJacobiansMatch(f, {bgi.data(), bai.data(), bgj.data(), baj.data()},
                       {nullptr, nullptr, nullptr, nullptr}, 1e-6);
  // Known answer: stationary GM over T has transition exp(-T/tau) and variance sigma^2 (1-phi^2).
  double phi = 0.0, sd = 0.0;
  gm.discretize(10.0, &phi, &sd);
  EXPECT_NEAR(phi, std::exp(-10.0 / 3600.0), 1e-15);
  EXPECT_NEAR(sd * sd, 1e-8 * (1.0 - phi * phi), 1e-20);
}

TEST_F(FactorJacobians, NodePriorFactor) {
  std::mt19937 rng(5);
  NodeValue x0;
  x0.p_w << 1, 2, 3;
  x0.q_wb = randomQuat(rng, 2.0);
  x0.v_w << 4, 5, 6;
  NodePriorFactor::Matrix15d S = NodePriorFactor::Matrix15d::Random();
  NodePriorFactor::Vector15d e = NodePriorFactor::Vector15d::Random();
  NodePriorFactor f(x0, S, e);
  Eigen::Vector3d p(1.5, 2.2, 2.9), v(4.1, 4.9, 6.3), bg(1e-3, 0, 0), ba(0.1, 0.2, 0.0);
  Eigen::Quaterniond q = x0.q_wb * quatFromRotationVector(Eigen::Vector3d(0.3, -0.2, 0.4));
  expectJacobiansMatch(f, {p.data(), q.coeffs().data(), v.data(), bg.data(), ba.data()},
                       {nullptr, &manifold_, nullptr, nullptr, nullptr}, 1e-6);
}

TEST_F(FactorJacobians, VehicleVelocityFactor) {
  Eigen::Vector3d v(8.0, 3.0, -0.2), bg(2e-4, -1e-4, 3e-4);
  Eigen::Quaterniond q = quatFromEuler(Eigen::Vector3d(0.05, -0.03, 1.2));
  double s = 2500e-6;
  const Eigen::Matrix3d C_vb = quatFromEuler(Eigen::Vector3d(0.01, -0.02, 0.04)).toRotationMatrix();
  const Eigen::Vector3d lever(-0.8, 0.5, 1.1), w_ie(3e-5, 0.0, -4e-5);
  VehicleObservation obs;
  obs.omega_raw_b << 0.05, -0.04, 0.3;
  obs.has_speed = true;
  obs.speed_m_s = 8.4;
  obs.row_std_m_s << 0.05, 0.1, 0.2;
  const VehicleVelocityFactor with_scale(obs, C_vb, lever, w_ie, true);
  ASSERT_TRUE(with_scale.usesScale());
  expectJacobiansMatch(with_scale, {q.coeffs().data(), v.data(), bg.data(), &s},
                       {&manifold_, nullptr, nullptr, nullptr}, 1e-6);
  obs.has_speed = false;  // NHC only: two rows, no scale block
  const VehicleVelocityFactor nhc(obs, C_vb, lever, w_ie, true);
  EXPECT_FALSE(nhc.usesScale());
  EXPECT_EQ(nhc.num_residuals(), 2);
  expectJacobiansMatch(nhc, {q.coeffs().data(), v.data(), bg.data()},
                       {&manifold_, nullptr, nullptr}, 1e-6);
}

TEST_F(FactorJacobians, OdometerScaleFactors) {
  double a = 1e-3, b = 1.5e-3;
  const OdometerScaleWalkFactor walk(1e-5, 2.0);
  expectJacobiansMatch(walk, {&a, &b}, {nullptr, nullptr}, 1e-6);
  const OdometerScalePriorFactor prior(0.0, 0.01);
  expectJacobiansMatch(prior, {&a}, {nullptr}, 1e-6);
  double r = 0.0;
  const double* pa[] = {&a};
  prior.Evaluate(pa, &r, nullptr);
  EXPECT_NEAR(r, 0.1, 1e-12);
}

TEST_F(FactorJacobians, NodeScalePriorFactor) {
  std::mt19937 rng(6);
  NodeValue x0;
  x0.p_w << 1, 2, 3;
  x0.q_wb = randomQuat(rng, 2.0);
  x0.v_w << 4, 5, 6;
  x0.odometer_scale = 1e-3;
  const NodeScalePriorFactor f(x0, NodeScalePriorFactor::Matrix16d::Random(),
                               NodeScalePriorFactor::Vector16d::Random());
  Eigen::Vector3d p(1.5, 2.2, 2.9), v(4.1, 4.9, 6.3), bg(1e-3, 0, 0), ba(0.1, 0.2, 0.0);
  double s = 2e-3;
  Eigen::Quaterniond q = x0.q_wb * quatFromRotationVector(Eigen::Vector3d(0.3, -0.2, 0.4));
  expectJacobiansMatch(f, {p.data(), q.coeffs().data(), v.data(), bg.data(), ba.data(), &s},
                       {nullptr, &manifold_, nullptr, nullptr, nullptr, nullptr}, 1e-6);
}

// The factor carries the EKF's model (filters/vehicle_velocity.h): at the origin of w the two
// differ only by the transport rate in the lever-arm term (~1e-6 m/s here).
TEST(VehicleVelocityFactorModel, EqualsTheEkfsVehicleVelocity) {
  NavState s;
  s.pos = {30.5 * kDegToRad, 114.3 * kDegToRad, 40.0};
  s.v_n << 9.0, -4.0, 0.3;
  s.q_nb = quatFromEuler(Eigen::Vector3d(0.04, -0.02, 2.1));
  const LocalFrame frame(s.pos);
  Eigen::Vector3d p_w, v_w;
  Eigen::Quaterniond q_wb;
  frame.fromNavState(s, &p_w, &v_w, &q_wb);
  VehicleGeometry g;
  g.C_vb = quatFromEuler(Eigen::Vector3d(0.01, -0.02, 0.04)).toRotationMatrix();
  g.lever_arm_b_m << -0.8, 0.5, 1.1;
  const Eigen::Vector3d omega_ib(0.05, -0.04, 0.3), bg(2e-4, -1e-4, 3e-4);
  VehicleObservation obs;
  obs.omega_raw_b = omega_ib + bg;
  obs.has_speed = true;
  obs.row_std_m_s.setOnes();
  const VehicleVelocityFactor f(obs, g.C_vb, g.lever_arm_b_m, frame.omega_ie_w(), false);
  Eigen::Vector3d r;
  const double* params[] = {q_wb.coeffs().data(), v_w.data(), bg.data()};
  ASSERT_TRUE(f.Evaluate(params, r.data(), nullptr));
  EXPECT_LT((r - vehicleVelocity(s, omega_ib, g)).norm(), 1e-5)
      << r.transpose() << " vs " << vehicleVelocity(s, omega_ib, g).transpose();
}

}  // namespace
}  // namespace graftnav
