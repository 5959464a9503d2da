// Ceres joint fit of the time offset (non-linear) with the other selected terms
// (mismatch/joint_fit.h): recovery on synthetic pairs made with the error model, agreement with
// the linear path where that is valid, and the covariance against a Monte-Carlo spread.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graftnav/imu/imu_error_model.h"
#include "graftnav/mismatch/joint_fit.h"
#include "graftnav/mismatch/time_offset.h"
#include "synthetic_imu.h"

namespace graftnav {
namespace {

// Sum of sinusoids per channel [omega (3), f (3)], integrated analytically.
struct Waves {
  std::array<std::vector<std::array<double, 3>>, 6> w;  // amplitude, angular frequency, phase
  Vector6d offset = Vector6d::Zero();
  Vector6d integral(double t) const {
    Vector6d out = offset * t;
    for (int c = 0; c < 6; ++c)
      for (const auto& s : w[c])
        out(c) += s[0] / s[1] * (std::cos(s[2]) - std::cos(s[1] * t + s[2]));
    return out;
  }
};

Waves carLikeWaves(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Waves m;
  const double amp[6] = {0.05, 0.05, 0.2, 1.2, 1.5, 0.5};
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k < 6; ++k)
      m.w[c].push_back(
          {amp[c] * (0.3 + U(rng)), 2.0 * M_PI * (0.02 + 0.6 * U(rng)), 2.0 * M_PI * U(rng)});
  m.offset << 0.0, 0.0, 0.0, 0.2, -0.1, -9.79;
  return m;
}

ImuSeries sample(const Waves& m, double rate_hz, double duration_s) {
  return test::sampleIntegral([&m](double t) { return m.integral(t); }, rate_hz, duration_s,
                              1000.0);
}

ImuErrorModel truthModel(double tau_s) {
  ImuErrorModel m;
  m.time_offset.tau_s = tau_s;
  m.lever_arm.r_m << 0.3, -0.2, 0.15;
  m.g_sensitivity.G(0, 0) = 4e-4;
  m.g_sensitivity.G(1, 1) = -3e-4;
  m.g_sensitivity.G(2, 1) = 3e-4;
  m.gyro.white_noise.density.setConstant(3e-4);
  m.accel.white_noise.density.setConstant(3e-3);
  m.gyro.constant_bias.b << 0.01, -0.015, 0.005;
  m.accel.constant_bias.b << 0.1, -0.05, 0.08;
  return m;
}

struct Fits {
  SelectionResult linear;
  JointFitResult joint;
  int to = -1, la = -1, gs = -1;  // positions in linear.selected / joint.terms
};

// Real = reference through the model; simulation = the reference itself. Linear fit of
// {time_offset (chord at the cross-correlation pivot), lever_arm, g_sensitivity}, then the joint
// Ceres fit from it.
Fits fitPair(const ImuSeries& reference, const ImuErrorModel& model, uint64_t seed) {
  const ImuSeries real = applyErrors(reference, model, seed);
  const GridSpec grid = commonGrid(reference, real, 0.05, 1.0);
  const BinnedImu x = binImu(reference, grid), y = binImu(real, grid);
  Eigen::MatrixXd r(grid.count, 6);
  r << y.omega_rad_s - x.omega_rad_s, y.f_m_s2 - x.f_m_s2;
  const TimeOffsetEstimate xc = estimateTimeOffset(reference, real);
  RegressorInputs ri;
  ri.reference = x;
  ri.time_offset_column = timeOffsetRegressor(reference, grid, xc.reliable ? xc.tau_s : 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(ri);
  std::vector<int> idx;
  int to_term = -1;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    const TermKind k = terms[t].kind();
    if (k == TermKind::time_offset) to_term = static_cast<int>(t);
    if (k == TermKind::time_offset || k == TermKind::lever_arm || k == TermKind::g_sensitivity)
      idx.push_back(static_cast<int>(t));
  }
  EXPECT_EQ(idx.size(), 3u);
  Fits f;
  f.linear = fitTerms(r, terms, idx);
  f.joint = jointFitWithTimeOffset(r, reference, grid, terms, f.linear, to_term);
  for (std::size_t k = 0; k < f.linear.selected.size(); ++k) {
    const TermKind kind = terms[f.linear.selected[k].term].kind();
    const int p = static_cast<int>(k);
    if (kind == TermKind::time_offset) f.to = p;
    if (kind == TermKind::lever_arm) f.la = p;
    if (kind == TermKind::g_sensitivity) f.gs = p;
  }
  return f;
}

// Normalized errors (estimate - truth) / sigma of tau, r_m and the determined G elements.
std::vector<double> normalizedErrors(const Fits& f, const ImuErrorModel& m) {
  std::vector<double> z;
  const TermFit& to = f.joint.terms[f.to];
  z.push_back((to.theta(0) - m.time_offset.tau_s) / to.sigma(0));
  const TermFit& la = f.joint.terms[f.la];
  for (int a = 0; a < 3; ++a) z.push_back((la.theta(a) - m.lever_arm.r_m(a)) / la.sigma(a));
  const TermFit& gs = f.joint.terms[f.gs];
  for (int k = 0; k < 9; ++k) {
    const double truth = m.g_sensitivity.G(k / 3, k % 3);
    if (std::isfinite(gs.sigma(k)) && gs.sigma(k) < 1e-3)
      z.push_back((gs.theta(k) - truth) / gs.sigma(k));
  }
  return z;
}

TEST(MismatchJointFit, RecoversLargeTimeOffsetLeverArmAndGSensitivity) {
  const ImuSeries ref = sample(carLikeWaves(11), 100.0, 200.0);
  const ImuErrorModel m = truthModel(0.035);  // 3.5 samples, 0.7 bins
  const Fits f = fitPair(ref, m, 21);
  ASSERT_TRUE(f.joint.converged) << f.joint.summary;
  ASSERT_GE(f.to, 0);
  ASSERT_GE(f.la, 0);
  ASSERT_GE(f.gs, 0);
  const std::vector<double> z = normalizedErrors(f, m);
  ASSERT_GE(z.size(), 7u);
  for (std::size_t k = 0; k < z.size(); ++k)
    EXPECT_LT(std::abs(z[k]), 3.0) << "parameter " << k << "; " << f.joint.summary;
  EXPECT_LT(f.joint.final_cost, f.joint.initial_cost + 1e-9);
  const TermFit& la_lin = f.linear.selected[f.la];
  std::printf("%s\nlever arm linear [%.4f %.4f %.4f] joint [%.4f %.4f %.4f] +- [%.4f %.4f %.4f]\n",
              f.joint.summary.c_str(), la_lin.theta(0), la_lin.theta(1), la_lin.theta(2),
              f.joint.terms[f.la].theta(0), f.joint.terms[f.la].theta(1),
              f.joint.terms[f.la].theta(2), f.joint.terms[f.la].sigma(0),
              f.joint.terms[f.la].sigma(1), f.joint.terms[f.la].sigma(2));
}

TEST(MismatchJointFit, AgreesWithTheLinearFitForASmallOffset) {
  const ImuSeries ref = sample(carLikeWaves(12), 100.0, 200.0);
  const ImuErrorModel m = truthModel(0.004);
  const Fits f = fitPair(ref, m, 22);
  ASSERT_TRUE(f.joint.converged) << f.joint.summary;
  for (std::size_t k = 0; k < f.linear.selected.size(); ++k) {
    const TermFit& a = f.linear.selected[k];
    const TermFit& b = f.joint.terms[k];
    ASSERT_EQ(a.theta.size(), b.theta.size());
    for (Eigen::Index j = 0; j < a.theta.size(); ++j) {
      if (!std::isfinite(a.sigma(j))) continue;
      EXPECT_LT(std::abs(a.theta(j) - b.theta(j)), 0.5 * a.sigma(j))
          << "term " << k << " element " << j << "; " << f.joint.summary;
      EXPECT_NEAR(b.sigma(j) / a.sigma(j), 1.0, 0.1) << "term " << k << " element " << j;
    }
  }
}

TEST(MismatchJointFit, CovarianceMatchesMonteCarloSpread) {
  const ImuSeries ref = sample(carLikeWaves(13), 100.0, 120.0);
  const ImuErrorModel m = truthModel(0.025);
  std::vector<double> z;
  std::vector<double> tau;
  double tau_sigma = 0.0;
  const int seeds = 8;
  for (int s = 0; s < seeds; ++s) {
    const Fits f = fitPair(ref, m, 100 + s);
    ASSERT_TRUE(f.joint.converged) << f.joint.summary;
    const std::vector<double> zs = normalizedErrors(f, m);
    z.insert(z.end(), zs.begin(), zs.end());
    tau.push_back(f.joint.terms[f.to].theta(0));
    tau_sigma += f.joint.terms[f.to].sigma(0) / seeds;
  }
  // Pooled RMS of the normalized errors (~100 values): 1 if the covariance is right.
  double ss = 0.0;
  for (double v : z) ss += v * v;
  const double rms = std::sqrt(ss / z.size());
  EXPECT_GT(rms, 1.0 / 1.5);
  EXPECT_LT(rms, 1.5);
  // The time offset alone: spread over the seeds against its stated sigma.
  double mean = 0.0;
  for (double v : tau) mean += v / seeds;
  double var = 0.0;
  for (double v : tau) var += (v - mean) * (v - mean) / (seeds - 1);
  EXPECT_GT(std::sqrt(var) / tau_sigma, 1.0 / 2.0);  // 8 seeds: the spread itself is +-25 %
  EXPECT_LT(std::sqrt(var) / tau_sigma, 2.0);
  RecordProperty("pooled_normalized_rms", std::to_string(rms));
  std::printf(
      "joint fit: pooled normalized error RMS %.3f over %zu values; tau spread %.3g s vs "
      "sigma %.3g s\n",
      rms, z.size(), std::sqrt(var), tau_sigma);
}

TEST(MismatchJointFit, RejectsBadInputs) {
  JointFitOptions o;
  o.chunk_bins = 1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  const ImuSeries ref = sample(carLikeWaves(14), 100.0, 20.0);
  const GridSpec grid = commonGrid(ref, ref, 0.05, 1.0);
  SelectionResult lin;
  EXPECT_THROW(jointFitWithTimeOffset(Eigen::MatrixXd::Zero(3, 6), ref, grid, {}, lin, 0),
               std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
