// Preintegration: against mechanization on a truth-by-construction trajectory, bias Jacobians
// against re-integration, covariance against Monte Carlo.
#include <gtest/gtest.h>

#include "graftnav/nav/rotation.h"
#include "graftnav/graph/imu_preintegration.h"
#include "graftnav/graph/local_frame.h"
#include "graftnav/graph/preintegration_factor.h"
#include "graph_scenario.h"
#include "test_support.h"

namespace graftnav {
namespace {

struct PredictionError {
  double pos_m, vel_m_s, att_rad;
};

// Predicts truth[j] from truth[i] through a preintegration of the ideal samples in between.
PredictionError predictFromTruth(const test::Scenario& sc, size_t i, size_t j, bool earth) {
  const LocalFrame frame(sc.truth.front().pos);
  ImuPreintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), {1e-4, 1e-3});
  for (size_t k = i; k < j; ++k) pre.integrate(k > 0 ? sc.ideal[k - 1] : sc.ideal[k], sc.ideal[k]);
  Eigen::Vector3d p_i, v_i, p_j, v_j;
  Eigen::Quaterniond q_i, q_j;
  frame.fromNavState(sc.truth[i], &p_i, &v_i, &q_i);
  frame.fromNavState(sc.truth[j], &p_j, &v_j, &q_j);
  const Eigen::Vector3d w = earth ? frame.omega_ie_w() : Eigen::Vector3d::Zero().eval();
  PreintegrationFactor f(&pre, w, frame.linearGravity(p_i));
  Eigen::Vector3d pp, vp;
  Eigen::Quaterniond qp;
  f.predict(p_i, q_i, v_i, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), &pp, &qp, &vp);
  return {(pp - p_j).norm(), (vp - v_j).norm(),
          rotationVectorFromQuat(qp.conjugate() * q_j).norm()};
}

// [dp, dv, Log(dR_ref^T dR)] of `p`: the increments a Jacobian test differentiates.
Eigen::VectorXd incrementsAbout(const ImuPreintegration& ref, const ImuPreintegration& p) {
  Eigen::VectorXd out(9);
  out.segment<3>(0) = p.deltaP();
  out.segment<3>(3) = p.deltaV();
  out.segment<3>(6) =
      rotationVectorFromQuat(Eigen::Quaterniond(ref.deltaR().transpose() * p.deltaR()));
  return out;
}

TEST(Preintegration, MatchesMechanizationOfAnalyticTrajectory) {
  const test::Scenario sc = test::makeScenario(32.0, 200.0, 20.0);
  for (size_t len : {200u, 2000u}) {  // 1 s and 10 s intervals
    const PredictionError e = predictFromTruth(sc, 400, 400 + len, true);
    const double T = len / 200.0;
    // Both are second-order schemes of the same physics: agree to far below any IMU's error.
    EXPECT_LT(e.pos_m, 2e-4 * T * T) << "interval " << T << " s";
    EXPECT_LT(e.vel_m_s, 1e-4 * T) << "interval " << T << " s";
    EXPECT_LT(e.att_rad, 2e-7 * T) << "interval " << T << " s";
  }
}

TEST(Preintegration, IgnoringEarthRotationLeavesVisibleErrors) {
  const test::Scenario sc = test::makeScenario(32.0, 200.0, 20.0);
  const PredictionError with = predictFromTruth(sc, 400, 800, true);
  const PredictionError without = predictFromTruth(sc, 400, 800, false);
  // Over 2 s the Earth rate turns the frame by 0.15 mrad and Coriolis (2 w v ~ 2.5 mm/s^2 at
  // 20 m/s, 30 deg N) moves the vehicle by millimetres: the switch must matter by far.
  EXPECT_GT(without.att_rad, 1e-4);
  EXPECT_GT(without.att_rad, 100.0 * with.att_rad);
  EXPECT_GT(without.vel_m_s, 100.0 * with.vel_m_s);
  EXPECT_GT(without.pos_m, 100.0 * with.pos_m);
}

TEST(Preintegration, BiasJacobiansMatchReintegration) {
  const test::Scenario sc = test::makeScenario(3.0);
  const Eigen::Vector3d bg0(1e-4, -2e-4, 5e-5), ba0(0.02, -0.01, 0.03);
  ImuPreintegration ref(bg0, ba0, {1e-4, 1e-3});
  ref.reintegrate(sc.ideal, 1, 400, bg0, ba0);
  // f(bg, ba) = [dp, dv, Log(dR0^T dR)] by full re-integration.
  auto f = [&](const Eigen::VectorXd& b) {
    ImuPreintegration p(bg0, ba0, {1e-4, 1e-3});
    p.reintegrate(sc.ideal, 1, 400, b.head<3>(), b.tail<3>());
    return incrementsAbout(ref, p);
  };
  Eigen::VectorXd b0(6);
  b0 << bg0, ba0;
  const Eigen::MatrixXd J_num = test::numericJacobian(f, b0, 1e-6);
  Eigen::MatrixXd J(9, 6);
  J.setZero();
  J.block<3, 3>(0, 0) = ref.dp_dbg();
  J.block<3, 3>(0, 3) = ref.dp_dba();
  J.block<3, 3>(3, 0) = ref.dv_dbg();
  J.block<3, 3>(3, 3) = ref.dv_dba();
  J.block<3, 3>(6, 0) = ref.dR_dbg();
  // The analytic Jacobians neglect the coning/sculling terms' bias dependence: 1e-3 relative.
  EXPECT_LT((J - J_num).norm(), 2e-3 * J_num.norm()) << "analytic\n" << J << "\nnumeric\n" << J_num;
  // First-order correction agrees with re-integration for a bias change of this size.
  const Eigen::Vector3d dbg(3e-4, 1e-4, -2e-4), dba(0.05, 0.02, -0.04);
  ImuPreintegration moved(bg0, ba0, {1e-4, 1e-3});
  moved.reintegrate(sc.ideal, 1, 400, bg0 + dbg, ba0 + dba);
  EXPECT_LT((ref.correctedDeltaP(bg0 + dbg, ba0 + dba) - moved.deltaP()).norm(), 1e-5);
  EXPECT_LT((ref.correctedDeltaV(bg0 + dbg, ba0 + dba) - moved.deltaV()).norm(), 1e-5);
  EXPECT_LT(rotationVectorFromQuat(
                Eigen::Quaterniond(ref.correctedDeltaR(bg0 + dbg).transpose() * moved.deltaR()))
                .norm(),
            1e-8);
}

// The scale-factor Jacobians (and the bias ones, which the scales divide) against re-integration
// about a non-zero linearization, and the first-order correction against re-integration.
TEST(Preintegration, ScaleFactorJacobiansMatchReintegration) {
  const test::Scenario sc = test::makeScenario(3.0);
  const Eigen::Vector3d bg0(1e-4, -2e-4, 5e-5), ba0(0.02, -0.01, 0.03);
  ImuScaleFactors s0;
  s0.gyro << 1e-3, -2e-3, 3e-3;
  s0.accel << -1e-3, 5e-4, 2e-3;
  auto integrate = [&](const Eigen::VectorXd& x) {  // x = (bg, ba, sg, sa)
    ImuScaleFactors s;
    s.gyro = x.segment<3>(6);
    s.accel = x.segment<3>(9);
    ImuPreintegration p(bg0, ba0, {1e-4, 1e-3});
    p.reintegrate(sc.ideal.data() + 1, 399, &sc.ideal[0], x.head<3>(), x.segment<3>(3), s);
    return p;
  };
  Eigen::VectorXd x0(12);
  x0 << bg0, ba0, s0.gyro, s0.accel;
  const ImuPreintegration ref = integrate(x0);
  ASSERT_TRUE(ref.withScale());
  auto f = [&](const Eigen::VectorXd& x) {
    const ImuPreintegration p = integrate(x);
    return incrementsAbout(ref, p);
  };
  const Eigen::MatrixXd J_num = test::numericJacobian(f, x0, 1e-6);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(9, 12);
  J.block<3, 3>(0, 0) = ref.dp_dbg();
  J.block<3, 3>(0, 3) = ref.dp_dba();
  J.block<3, 3>(0, 6) = ref.dp_dsg();
  J.block<3, 3>(0, 9) = ref.dp_dsa();
  J.block<3, 3>(3, 0) = ref.dv_dbg();
  J.block<3, 3>(3, 3) = ref.dv_dba();
  J.block<3, 3>(3, 6) = ref.dv_dsg();
  J.block<3, 3>(3, 9) = ref.dv_dsa();
  J.block<3, 3>(6, 0) = ref.dR_dbg();
  J.block<3, 3>(6, 6) = ref.dR_dsg();
  // Column by column: the scale columns are as large as the rotation and velocity the interval
  // holds; each must match to the coning/sculling terms neglected (1e-3 relative).
  for (int c = 0; c < 12; ++c) {
    EXPECT_LT((J.col(c) - J_num.col(c)).norm(), 2e-3 * J_num.col(c).norm() + 1e-12)
        << "column " << c << "\nanalytic " << J.col(c).transpose() << "\nnumeric  "
        << J_num.col(c).transpose();
  }
  // First-order correction for a 1000 ppm change of every scale factor.
  Eigen::VectorXd x1 = x0;
  x1.segment<6>(6) += Eigen::VectorXd::Constant(6, 1e-3);
  const ImuPreintegration moved = integrate(x1);
  ImuScaleFactors s1;
  s1.gyro = x1.segment<3>(6);
  s1.accel = x1.segment<3>(9);
  const Eigen::Vector3d dp_first = ref.correctedDeltaP(bg0, ba0, s1);
  const Eigen::Vector3d dv_first = ref.correctedDeltaV(bg0, ba0, s1);
  // The correction itself is ~1e-3 of the increments; what is left is second order.
  EXPECT_GT((moved.deltaP() - ref.deltaP()).norm(), 1e-5);
  EXPECT_LT((dp_first - moved.deltaP()).norm(), 1e-3 * (moved.deltaP() - ref.deltaP()).norm());
  EXPECT_LT((dv_first - moved.deltaV()).norm(), 1e-3 * (moved.deltaV() - ref.deltaV()).norm());
  EXPECT_LT(
      rotationVectorFromQuat(
          Eigen::Quaterniond(ref.correctedDeltaR(bg0, s1).transpose() * moved.deltaR()))
          .norm(),
      1e-3 * rotationVectorFromQuat(Eigen::Quaterniond(ref.deltaR().transpose() * moved.deltaR()))
                 .norm());
}

// Without scale factors the samples are corrected exactly as before scale states existed, and
// zero linearization scales give the same increments.
TEST(Preintegration, ZeroScaleFactorsGiveTheUnscaledIncrements) {
  const test::Scenario sc = test::makeScenario(3.0);
  const Eigen::Vector3d bg(1e-4, -2e-4, 5e-5), ba(0.02, -0.01, 0.03);
  ImuPreintegration a(bg, ba, {1e-4, 1e-3}), b(bg, ba, {1e-4, 1e-3});
  a.reintegrate(sc.ideal.data() + 1, 399, &sc.ideal[0], bg, ba);
  b.reintegrate(sc.ideal.data() + 1, 399, &sc.ideal[0], bg, ba, ImuScaleFactors());
  EXPECT_FALSE(a.withScale());
  EXPECT_TRUE(b.withScale());
  EXPECT_EQ(a.deltaP(), b.deltaP());
  EXPECT_EQ(a.deltaV(), b.deltaV());
  EXPECT_EQ(a.deltaR(), b.deltaR());
  EXPECT_LT((a.dv_dbg() - b.dv_dbg()).norm(), 1e-12 * a.dv_dbg().norm());
  EXPECT_GT(b.dR_dsg().norm(), 0.0);
}

TEST(Preintegration, CovarianceMatchesMonteCarlo) {
  const test::Scenario sc = test::makeScenario(1.0);
  const PreintegrationNoise noise{2e-3, 2e-2};  // large, MEMS-like x10, so errors dominate
  const size_t kRuns = 600;
  ImuPreintegration nominal(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), noise);
  nominal.reintegrate(sc.ideal, 0, sc.ideal.size(), Eigen::Vector3d::Zero(),
                      Eigen::Vector3d::Zero());
  test::ImuErrors err;
  err.arw_rad_sqrt_s = noise.arw_rad_sqrt_s;
  err.vrw_m_s_sqrt_s = noise.vrw_m_s_sqrt_s;
  std::vector<Eigen::Matrix<double, 9, 1>> samples;
  for (size_t r = 0; r < kRuns; ++r) {
    const ImuSeries noisy = test::addImuErrors(sc.ideal, err, 1000u + static_cast<unsigned>(r));
    ImuPreintegration p(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), noise);
    p.reintegrate(noisy, 0, noisy.size(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    Eigen::Matrix<double, 9, 1> e;
    e.segment<3>(0) = p.deltaP() - nominal.deltaP();
    e.segment<3>(3) = p.deltaV() - nominal.deltaV();
    e.segment<3>(6) =
        rotationVectorFromQuat(Eigen::Quaterniond(nominal.deltaR().transpose() * p.deltaR()));
    samples.push_back(e);
  }
  Eigen::Matrix<double, 9, 9> S = Eigen::Matrix<double, 9, 9>::Zero();
  for (const auto& e : samples) S += e * e.transpose();
  S /= static_cast<double>(kRuns);
  const Eigen::Matrix<double, 9, 9>& P = nominal.covariance();
  // Variance of a sample variance with 600 runs: sqrt(2/600) = 5.8 %; allow 4 sigma.
  for (int i = 0; i < 9; ++i) {
    EXPECT_NEAR(S(i, i) / P(i, i), 1.0, 0.23) << "diagonal " << i;
  }
  // Position-velocity correlation (dp = integral of dv): ~ sqrt(3)/2.
  for (int i = 0; i < 3; ++i) {
    const double rho_mc = S(i, 3 + i) / std::sqrt(S(i, i) * S(3 + i, 3 + i));
    const double rho = P(i, 3 + i) / std::sqrt(P(i, i) * P(3 + i, 3 + i));
    EXPECT_NEAR(rho_mc, rho, 0.08) << "axis " << i;
  }
}

}  // namespace
}  // namespace graftnav
