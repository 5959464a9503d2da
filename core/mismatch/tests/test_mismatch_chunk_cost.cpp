// The joint time-offset fit's residual blocks (ChunkCost, core/mismatch/src/selection/joint_fit_cost.h):
// the analytic Jacobian in theta and in tau against central differences of the block's own
// residuals, on the chunk at the record's start (whose first row keeps the stationary variance)
// and on one inside the record (whose first row whitens against the bin before it).
// The tau Jacobian takes the reference's rate from CumulativeImu::rateAt, the derivative of the
// cubic Hermite curve; on uniformly sampled stretches at() is band limited instead, so there the
// Jacobian in tau is the Hermite curve's, close to but not the derivative of the residual.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "../src/selection/joint_fit_cost.h"
#include "graftnav/mismatch/common_grid.h"
#include "synthetic_imu.h"
#include "test_support.h"

namespace graftnav {
namespace {

using joint_fit_detail::ChunkCost;
using joint_fit_detail::ColumnRef;
using joint_fit_detail::JointData;

// Smooth motion with a little 12-Hz vibration on every channel, integrated analytically.
Vector6d motionIntegral(double t) {
  Vector6d out;
  for (int c = 0; c < 6; ++c) {
    const double a = c < 3 ? 0.2 : 1.5, w1 = 2.0 * M_PI * (0.11 + 0.07 * c), w2 = 2.0 * M_PI * 12.0;
    out(c) = a / w1 * (1.0 - std::cos(w1 * t + 0.3 * c)) + 0.05 * a / w2 * (1.0 - std::cos(w2 * t));
  }
  out(5) -= 9.79 * t;
  return out;
}

// Samples of motionIntegral at 100 Hz from t0_s, each interval 1 % longer or shorter than the one
// before when `jitter` (CumulativeImu then interpolates with the Hermite curve throughout).
ImuSeries sampleMotion(double duration_s, double t0_s, bool jitter) {
  if (!jitter) return test::sampleIntegral(motionIntegral, 100.0, duration_s, t0_s);
  ImuSeries out;
  double t = 0.0;
  for (int k = 0; t < duration_s; ++k) {
    const double dt = 0.01 * (1.0 + 0.01 * ((k % 3) - 1));
    const Vector6d inc = motionIntegral(t + dt) - motionIntegral(t);
    ImuSample s;
    s.t_s = t0_s + t + dt;
    s.dt_s = dt;
    s.dtheta_rad = inc.head<3>();
    s.dvel_m_s = inc.tail<3>();
    out.push_back(s);
    t += dt;
  }
  return out;
}

// A joint-fit problem of `n` bins with three free parameters (two regressors on every channel,
// one on the accelerometers only), a fixed-term contribution and random residuals; the
// regressors were built at a 3-ms pivot.
struct ChunkProblem {
  ImuSeries reference;
  std::unique_ptr<CumulativeImu> cum;
  Eigen::MatrixXd r;
  std::vector<Eigen::VectorXd> u;
  JointData d;

  ChunkProblem(int n, bool jitter) {
    reference = sampleMotion(0.05 * n + 2.0, 1000.0, jitter);
    cum = std::make_unique<CumulativeImu>(reference);
    std::mt19937_64 rng(41);
    std::normal_distribution<double> N(0.0, 1.0);
    d.grid.t_begin_s = 1000.5;
    d.grid.bin_s = 0.05;
    d.grid.count = n;
    r.resize(n, kMismatchChannels);
    d.X.resize(n, kMismatchChannels);
    d.K.resize(n, kMismatchChannels);
    d.dK.resize(n, kMismatchChannels);
    for (int i = 0; i < n; ++i) {
      d.X.row(i) = ((cum->at(d.grid.binStart(i + 1)) - cum->at(d.grid.binStart(i))) / d.grid.bin_s)
                       .transpose();
      for (int c = 0; c < kMismatchChannels; ++c) {
        r(i, c) = 0.01 * N(rng);
        d.K(i, c) = 1e-3 * std::sin(0.05 * i + c);
        d.dK(i, c) = 1e-3 * 0.05 / d.grid.bin_s * std::cos(0.05 * i + c);
      }
    }
    for (int k = 0; k < 3; ++k) {
      Eigen::VectorXd col(n);
      for (int i = 0; i < n; ++i) col(i) = std::sin(0.03 * (k + 1) * i) + 0.2 * N(rng);
      u.push_back(col);
    }
    d.r = &r;
    d.cum = cum.get();
    d.pivot = 0.003;
    d.P = 3;
    for (int c = 0; c < kMismatchChannels; ++c) {
      for (int k = 0; k < 3; ++k) {
        if (k == 2 && c < 3) continue;  // the third regressor acts on the accelerometers only
        Eigen::VectorXd du(n);
        for (int i = 0; i < n; ++i)
          du(i) = 0.03 * (k + 1) / d.grid.bin_s * std::cos(0.03 * (k + 1) * i) + 0.1 * N(rng);
        d.cols[c].push_back(ColumnRef{k, u[k].data(), du, {}});
      }
      d.rho(c) = 0.2 + 0.1 * c;
      d.w(c) = 1.0 / (0.01 + 0.002 * c);
    }
  }
};

// Residuals of `cost` at x = [theta; tau].
Eigen::VectorXd residualsAt(const ChunkCost& cost, const Eigen::VectorXd& x, int P) {
  const Eigen::VectorXd theta = x.head(P);
  const double tau = x(P);
  const double* params[2] = {theta.data(), &tau};
  Eigen::VectorXd res(cost.num_residuals());
  EXPECT_TRUE(cost.Evaluate(params, res.data(), nullptr));
  return res;
}

// Worst difference between the analytic and the central-difference Jacobian over two chunks,
// relative to the largest element: {theta, tau}.
std::pair<double, double> jacobianErrors(const ChunkProblem& p) {
  const int P = p.d.P;
  Eigen::VectorXd x0(P + 1);
  x0 << 0.02, -0.01, 0.005, 0.0041;  // theta, then tau (s) 1.1 ms from the pivot
  std::pair<double, double> worst{0.0, 0.0};
  for (const auto& [i0, i1] : {std::pair<int, int>{0, 40}, std::pair<int, int>{120, 160}}) {
    const ChunkCost cost(&p.d, i0, i1);
    const int m = cost.num_residuals();
    EXPECT_EQ(m, kMismatchChannels * (i1 - i0));
    // Analytic Jacobians: theta row-major (m x P), tau (m x 1).
    const Eigen::VectorXd theta = x0.head(P);
    const double tau = x0(P);
    const double* params[2] = {theta.data(), &tau};
    Eigen::VectorXd res(m), J_tau(m);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J_theta(m, P);
    double* jac[2] = {J_theta.data(), J_tau.data()};
    EXPECT_TRUE(cost.Evaluate(params, res.data(), jac));
    EXPECT_LT((res - residualsAt(cost, x0, P)).cwiseAbs().maxCoeff(), 1e-15)
        << "residuals with and without Jacobians differ";
    // Steps: theta enters linearly; tau through the reference's integral, whose third derivative
    // (12-Hz vibration) sets the central difference's error at step^2.
    const auto f = [&](const Eigen::VectorXd& x) { return residualsAt(cost, x, P); };
    const Eigen::MatrixXd N_theta = test::numericJacobian(f, x0, 1e-6).leftCols(P);
    const Eigen::VectorXd N_tau = test::numericJacobian(f, x0, 1e-7).col(P);
    const double scale_theta = N_theta.cwiseAbs().maxCoeff(),
                 scale_tau = N_tau.cwiseAbs().maxCoeff();
    EXPECT_GT(scale_theta, 0.0);
    EXPECT_GT(scale_tau, 0.0);
    worst.first = std::max(
        worst.first, (Eigen::MatrixXd(J_theta) - N_theta).cwiseAbs().maxCoeff() / scale_theta);
    worst.second = std::max(worst.second, (J_tau - N_tau).cwiseAbs().maxCoeff() / scale_tau);
  }
  return worst;
}

// Where the reference is interpolated by the Hermite curve (jittered samples), the Jacobian is the
// derivative of the residual in theta and in tau.
TEST(MismatchChunkCost, AnalyticJacobianMatchesCentralDifferences) {
  const auto [err_theta, err_tau] = jacobianErrors(ChunkProblem(200, /*jitter=*/true));
  EXPECT_LT(err_theta, 1e-7);
  EXPECT_LT(err_tau, 1e-5);
}

// On a uniformly sampled record the residual uses the band-limited integral and the tau Jacobian
// the Hermite curve's rate: the theta part stays exact and the tau part is off by a few tenths of
// a percent with 12-Hz vibration at 100 Hz (0.39 % here), which slows Levenberg-Marquardt at
// most and moves tau's covariance by as much.
TEST(MismatchChunkCost, TauJacobianOnUniformSamplesIsTheHermiteRate) {
  const auto [err_theta, err_tau] = jacobianErrors(ChunkProblem(200, /*jitter=*/false));
  EXPECT_LT(err_theta, 1e-7);
  EXPECT_LT(err_tau, 1e-2);
}

}  // namespace
}  // namespace graftnav
