// The stochastic IMU error terms (white noise, Gauss-Markov, random walk) against their sampling
// distributions (seeded, tolerances from the estimator's standard error).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <numeric>
#include <vector>

#include "graftnav/imu/gauss_markov.h"
#include "graftnav/imu/imu_error_model.h"
#include "graftnav/nav/rotation.h"
#include "imu_test_series.h"

namespace graftnav {
namespace {

using namespace imu_test;  // NOLINT(build/namespaces): the shared test inputs

// ---- stochastic terms -------------------------------------------------------------------

class GaussMarkovAtRate : public ::testing::TestWithParam<double> {};

// Sample autocorrelation at lag m, pooled over the three axes of a (n x 3) set of series.
double sampleAutocorr(const std::vector<Vector3d>& x, int lag) {
  double num = 0.0, den = 0.0;
  for (int i = 0; i < 3; ++i) {
    double mean = 0.0;
    for (const auto& v : x) mean += v[i];
    mean /= x.size();
    for (size_t k = 0; k < x.size(); ++k) {
      const double d = x[k][i] - mean;
      den += d * d;
      if (k + lag < x.size()) num += d * (x[k + lag][i] - mean);
    }
  }
  return num / den;
}

TEST_P(GaussMarkovAtRate, StationaryVarianceAndCorrelationMatchExactDiscretization) {
  const double rate_hz = GetParam();
  const double dt = 1.0 / rate_hz;
  // tau comparable to dt so that an approximate (Euler) discretization would be caught: at
  // 100 Hz, q = 2 sigma^2 dt / tau would inflate the stationary variance by 21 %.
  const double tau = 0.05;
  const Vector3d sigma(1e-4, 2e-4, 5e-5);  // rad/s
  ImuErrorModel m;
  m.gyro.bias_instability.sigma = sigma;
  m.gyro.bias_instability.tau_s = tau;
  const int n = 200000;
  const ImuSeries out = applyErrors(constantSeries(n, dt, Vector3d::Zero(), kF), m, 2024);
  std::vector<Vector3d> b(n);
  for (int k = 0; k < n; ++k) b[k] = (out[k].dtheta_rad / dt).cwiseQuotient(sigma);  // N(0,1)
  const double rho = std::exp(-dt / tau);
  // Variance of the (unit) process, pooled over 3 axes: standard error of s^2 for AR(1),
  // sqrt(2 (1 + rho^2) / (N (1 - rho^2))).
  double var = 0.0;
  for (const auto& v : b) var += v.squaredNorm();
  var /= 3.0 * n;
  const double se_var = std::sqrt(2.0 * (1 + rho * rho) / (3.0 * n * (1 - rho * rho)));
  EXPECT_NEAR(var, 1.0, 5.0 * se_var);
  // Bartlett's formula for the standard error of the lag-m autocorrelation of an AR(1).
  auto se_corr = [&](int lag) {
    const double r2m = std::pow(rho, 2 * lag);
    return std::sqrt(((1 + rho * rho) * (1 - r2m) / (1 - rho * rho) - 2.0 * lag * r2m) / (3.0 * n));
  };
  EXPECT_NEAR(sampleAutocorr(b, 1), rho, 5.0 * se_corr(1));
  const int lag_tau = static_cast<int>(std::lround(tau / dt));
  EXPECT_NEAR(sampleAutocorr(b, lag_tau), std::exp(-1.0), 5.0 * se_corr(lag_tau));
  // The one-step coefficients themselves.
  EXPECT_DOUBLE_EQ(GaussMarkov::transition(dt, tau), rho);
  EXPECT_NEAR(GaussMarkov::drivingNoiseStd(2.0, dt, tau), 2.0 * std::sqrt(1 - rho * rho), 1e-15);
}

INSTANTIATE_TEST_SUITE_P(Rates, GaussMarkovAtRate, ::testing::Values(100.0, 200.0));

TEST(GaussMarkov, StationaryStartAndZeroStart) {
  GaussMarkovParams p;
  p.sigma = Vector3d(1.0, 2.0, 3.0);
  p.tau_s = 100.0;
  // Ensemble of first samples: variance sigma^2 when stationary, exactly zero otherwise.
  StandardNormalSampler rng(5);
  Vector3d var = Vector3d::Zero();
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    GaussMarkov gm(p);
    gm.initialize(rng);
    var += gm.state().cwiseAbs2();
  }
  var /= n;
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(var[i] / (p.sigma[i] * p.sigma[i]), 1.0, 5.0 * std::sqrt(2.0 / n));
  p.start_stationary = false;
  GaussMarkov gm0(p);
  gm0.initialize(rng);
  EXPECT_EQ(gm0.state(), Vector3d::Zero());
  // tau = inf: a random constant.
  p.tau_s = std::numeric_limits<double>::infinity();
  p.start_stationary = true;
  GaussMarkov gmc(p);
  gmc.initialize(rng);
  const Vector3d x0 = gmc.state();
  gmc.propagate(10.0, rng);
  EXPECT_EQ(gmc.state(), x0);
  EXPECT_THROW(GaussMarkov(GaussMarkovParams{Vector3d::Ones(), -1.0, true}), std::invalid_argument);
}

class WhiteNoiseAtRate : public ::testing::TestWithParam<double> {};

TEST_P(WhiteNoiseAtRate, IncrementStdIsDensityTimesSqrtDt) {
  const double dt = 1.0 / GetParam();
  ImuErrorModel m;
  m.gyro.white_noise.density = Vector3d(1e-4, 2e-4, 4e-4);   // ARW rad/sqrt(s)
  m.accel.white_noise.density = Vector3d(1e-3, 5e-4, 2e-3);  // VRW m/s/sqrt(s)
  const int n = 100000;
  const ImuSeries in = constantSeries(n, dt, kOmega, kF);
  const ImuSeries out = applyErrors(in, m, 11);
  Vector3d sg = Vector3d::Zero(), sa = Vector3d::Zero(), mg = Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const Vector3d eg = out[k].dtheta_rad - in[k].dtheta_rad;
    const Vector3d ea = out[k].dvel_m_s - in[k].dvel_m_s;
    sg += eg.cwiseAbs2();
    sa += ea.cwiseAbs2();
    mg += eg;
  }
  const double se_std = 1.0 / std::sqrt(2.0 * n);  // relative standard error of a sample std
  for (int i = 0; i < 3; ++i) {
    const double std_g = std::sqrt(sg[i] / n), std_a = std::sqrt(sa[i] / n);
    EXPECT_NEAR(std_g / (m.gyro.white_noise.density[i] * std::sqrt(dt)), 1.0, 5.0 * se_std);
    EXPECT_NEAR(std_a / (m.accel.white_noise.density[i] * std::sqrt(dt)), 1.0, 5.0 * se_std);
    EXPECT_NEAR(mg[i] / n, 0.0, 5.0 * m.gyro.white_noise.density[i] * std::sqrt(dt / n));
  }
}

INSTANTIATE_TEST_SUITE_P(Rates, WhiteNoiseAtRate, ::testing::Values(100.0, 200.0));

TEST(ImuErrorModel, MeanRateOfArwNoiseOverTHasStdArwOverSqrtT) {
  // Seed Eq. 12: D = sigma_RW / sqrt(t_static), checked on 1 s and 4 s averages at 200 Hz.
  const double dt = 0.005, arw = 3e-4;
  ImuErrorModel m;
  m.gyro.white_noise.density.setConstant(arw);
  const int n = 800000;
  const ImuSeries out = applyErrors(constantSeries(n, dt, Vector3d::Zero(), kF), m, 3);
  for (double T : {1.0, 4.0}) {
    const int per = static_cast<int>(std::lround(T / dt));
    const int windows = n / per;
    double ss = 0.0;
    for (int w = 0; w < windows; ++w) {
      Vector3d sum = Vector3d::Zero();
      for (int k = w * per; k < (w + 1) * per; ++k) sum += out[k].dtheta_rad;
      ss += (sum / T).squaredNorm();
    }
    const int count = 3 * windows;
    const double std_mean = std::sqrt(ss / count);
    EXPECT_NEAR(std_mean / (arw / std::sqrt(T)), 1.0, 5.0 * std::sqrt(0.5 / count)) << "T " << T;
  }
}

TEST(ImuErrorModel, BiasRandomWalkStepsHaveStdDensityTimesSqrtDt) {
  const double dt = 0.01;
  ImuErrorModel m;
  m.accel.bias_random_walk.density = Vector3d(1e-4, 3e-4, 2e-5);  // m/s^2/sqrt(s)
  const int n = 50000;
  const ImuSeries in = constantSeries(n, dt, kOmega, kF);
  const ImuSeries out = applyErrors(in, m, 8);
  Vector3d prev = (out[0].dvel_m_s - in[0].dvel_m_s) / dt;
  EXPECT_LT(prev.norm(), 1e-12);  // b_0 = 0
  Vector3d ss = Vector3d::Zero();
  for (int k = 1; k < n; ++k) {
    const Vector3d b = (out[k].dvel_m_s - in[k].dvel_m_s) / dt;
    ss += (b - prev).cwiseAbs2();
    prev = b;
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::sqrt(ss[i] / (n - 1)) / (m.accel.bias_random_walk.density[i] * std::sqrt(dt)),
                1.0, 5.0 * std::sqrt(0.5 / n));
  }
}

}  // namespace
}  // namespace graftnav
