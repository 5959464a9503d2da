#include <gtest/gtest.h>

#include "graftnav/nav/mechanization.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/filters/ins_error_model.h"
#include "ekf_scenario.h"
#include "test_support.h"

namespace graftnav {
namespace {

using namespace ekf;

using test::movingState;

const Eigen::Vector3d kOmega_b(0.01, -0.02, 0.1);
const Eigen::Vector3d kF_b(0.5, 0.3, -9.7);

// Mechanizes `steps` samples of length h with constant body rate and specific force, adding the
// residual sensor errors of x (computed - true) to the increments.
NavState mechanize(NavState s, const ErrorState& x, int steps, double h) {
  Strapdown sd(s);
  for (int k = 1; k <= steps; ++k) {
    ImuSample imu;
    imu.t_s = s.t_s + k * h;
    imu.dt_s = h;
    const Eigen::Vector3d w = test::perturbedBodyRate(kOmega_b, x);
    const Eigen::Vector3d f =
        kF_b + x.segment<3>(kAccelBias) + kF_b.cwiseProduct(x.segment<3>(kAccelScale));
    imu.dtheta_rad = w * h;
    imu.dvel_m_s = f * h;
    sd.step(imu);
  }
  return sd.state();
}

TEST(InsErrorModel, AnalyticTransitionMatchesNumericLinearizationOfMechanization) {
  const NavState truth0 = movingState();
  const int steps = 200;  // 1 s at 200 Hz
  const double h = 0.005;
  const NavState truth1 = mechanize(truth0, ErrorState::Zero(), steps, h);
  // Central differences in scaled coordinates: steps large enough that the round-off of
  // latitude/longitude (~1e-9 m) does not swamp entries of ~1e-6, small enough to stay linear
  // (central differences cancel the quadratic terms).
  ErrorState scale;
  scale << 0.5, 0.5, 0.5, 0.1, 0.1, 0.1, 1e-2, 1e-2, 1e-2, 1e-4, 1e-4, 1e-4, 1e-2, 1e-2, 1e-2, 1e-3,
      1e-3, 1e-3, 1e-3, 1e-3, 1e-3;
  auto propagate = [&](const Eigen::VectorXd& u) -> Eigen::VectorXd {
    const ErrorState x = scale.cwiseProduct(ErrorState(u));
    const Eigen::VectorXd x0 = x;
    const NavState c1 = mechanize(perturbNavState(truth0, x), x, steps, h);
    Eigen::VectorXd out = x0;
    out.head<9>() = navErrorPsi(c1, truth1);
    return out;
  };
  const Eigen::MatrixXd Phi_num =
      test::numericJacobian(propagate, Eigen::VectorXd::Zero(kStateDim), 1.0) *
      scale.cwiseInverse().asDiagonal();

  // Analytic: product of per-sample transitions along the true trajectory.
  ImuProfile profile;  // no Gauss-Markov decay in the mechanization: T = infinity
  profile.gyro_bias_corr_time_s = profile.accel_bias_corr_time_s = profile.scale_corr_time_s = 0;
  ErrorCov Phi = ErrorCov::Identity(), step_phi, Qd;
  NavState s = truth0;
  const ErrorState q = ErrorState::Zero();
  for (int k = 0; k < steps; ++k) {
    const NavState next = mechanize(s, ErrorState::Zero(), 1, h);
    NavState mid = s;  // F at the mid-interval state
    mid.pos = {0.5 * (s.pos.lat_rad + next.pos.lat_rad), 0.5 * (s.pos.lon_rad + next.pos.lon_rad),
               0.5 * (s.pos.h_m + next.pos.h_m)};
    mid.v_n = 0.5 * (s.v_n + next.v_n);
    mid.q_nb = s.q_nb.slerp(0.5, next.q_nb);
    discretize(errorDynamics(mid, kOmega_b, kF_b, profile), q, h, &step_phi, &Qd);
    Phi = step_phi * Phi;
    s = next;
  }
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < kStateDim; ++j) {
      // 0.5 % relative: the mechanization's within-step terms (1/6 dtheta x (dtheta x dv)) give
      // the discrete map an O(h^2) direct gyro-to-velocity sensitivity the continuous F lacks.
      EXPECT_NEAR(Phi_num(i, j), Phi(i, j), 2e-7 + 5e-3 * std::abs(Phi(i, j)))
          << "Phi(" << i << "," << j << ")";
    }
  }
  // The blocks this test leans on are not trivially zero.
  EXPECT_GT(std::abs(Phi(kVel, kAtt + 1)), 1.0);             // f x psi
  EXPECT_GT(std::abs(Phi(kAtt + 2, kGyroScale + 2)), 0.05);  // omega_z scale
}

TEST(InsErrorModel, PerturbAndErrorAreInverse) {
  const NavState t = movingState();
  ErrorState x = ErrorState::Zero();
  x.head<9>() << 3.0, -2.0, 1.0, 0.1, -0.2, 0.05, 1e-3, -2e-3, 5e-3;
  const auto e = navErrorPsi(perturbNavState(t, x), t);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(e[i], x[i], 1e-6 * (1.0 + std::abs(x[i]) * 100));
  const NavState back = correctNavState(perturbNavState(t, x), x);
  EXPECT_NEAR(navErrorPsi(back, t).norm(), 0.0, 1e-5);
}

TEST(InsErrorModel, LeverArmPositionJacobianMatchesNumeric) {
  const NavState t = movingState();
  const Eigen::Vector3d l(0.8, -0.4, -1.5);
  const Geodetic gnss = antennaPosition(t, l);
  auto f = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    return gnssPositionInnovation(perturbNavState(t, ErrorState(x)), l, gnss);
  };
  const Eigen::MatrixXd Hn = test::numericJacobian(f, Eigen::VectorXd::Zero(kStateDim), 1e-4);
  const auto H = gnssPositionJacobian(t, l);
  // offsetByNed is first order in curvature: ~1e-6 relative in the identity block.
  EXPECT_LT((Hn - H).cwiseAbs().maxCoeff(), 1e-5) << Hn << "\n\n" << H;
  EXPECT_NEAR(f(Eigen::VectorXd::Zero(kStateDim)).norm(), 0.0, 1e-6);
}

TEST(InsErrorModel, LeverArmVelocityJacobianMatchesNumeric) {
  const NavState t = movingState();
  const Eigen::Vector3d l(0.8, -0.4, -1.5);
  const Eigen::Vector3d v_gnss = antennaVelocity(t, kOmega_b, l);
  auto f = [&](const Eigen::VectorXd& xv) -> Eigen::VectorXd {
    const ErrorState x = xv;
    const Eigen::Vector3d w = test::perturbedBodyRate(kOmega_b, x);
    return antennaVelocity(perturbNavState(t, x), w, l) - v_gnss;
  };
  const Eigen::MatrixXd Hn = test::numericJacobian(f, Eigen::VectorXd::Zero(kStateDim), 1e-4);
  const auto H = gnssVelocityJacobian(t, kOmega_b, l);
  EXPECT_LT((Hn - H).cwiseAbs().maxCoeff(), 1e-6) << Hn << "\n\n" << H;
}

TEST(InsErrorModel, DiscreteNoiseMatchesGaussMarkovVariance) {
  // One Gauss-Markov state alone: Qd over dt must be sigma^2 (1 - exp(-2 dt / T)) to 2nd order.
  ImuProfile p;
  p.gyro_bias_instability_rad_s = 1e-5;
  p.gyro_bias_corr_time_s = 100.0;
  NavState s = movingState();
  ErrorCov Phi, Qd;
  const double dt = 1.0;
  discretize(errorDynamics(s, kOmega_b, kF_b, p), continuousNoiseDensity(p), dt, &Phi, &Qd);
  const double exact = 1e-10 * (1.0 - std::exp(-2.0 * dt / 100.0));
  EXPECT_NEAR(Qd(kGyroBias, kGyroBias), exact, 1e-4 * exact);
  EXPECT_NEAR(Phi(kGyroBias, kGyroBias), std::exp(-dt / 100.0), 1e-6);
}

}  // namespace
}  // namespace graftnav
