// Mismatch finder, slow noise: bias wander is not claimed as temperature, and the fast (GLS,
// sandwich) and slow (block mean, random walk) terms' sigmas are calibrated under it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "graftnav/eval/evaluation.h"
#include "graftnav/imu/gauss_markov.h"
#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/mismatch/term_spec.h"
#include "graftnav/mismatch/time_offset.h"
#include "graftnav/nav/rotation.h"
#include "synthetic_imu.h"
#include "mismatch_signal_fixture.h"

namespace graftnav {
namespace {

using namespace mismatch_test;  // the shared fixtures of mismatch_signal_fixture.h

// Adds to each channel c of r a stationary Gauss-Markov wander of 1-sigma sd(c) and correlation
// time tau_s (bins of bin_s); channels with sd 0 are skipped without drawing.
void addGaussMarkovWander(Eigen::MatrixXd* r, const Eigen::Matrix<double, 6, 1>& sd, double bin_s,
                          double tau_s, uint64_t seed) {
  StandardNormalSampler rng(seed);
  const double phi = std::exp(-bin_s / tau_s);
  for (int c = 0; c < 6; ++c) {
    if (sd(c) == 0.0) continue;
    double b = rng.next();
    for (int i = 0; i < r->rows(); ++i) {
      b = phi * b + std::sqrt(1.0 - phi * phi) * rng.next();
      (*r)(i, c) += sd(c) * b;
    }
  }
}

// Car motion with minutes-long parts: a slow speed-up and slow-down along and across.
Motion slowDriveMotion() {
  Motion m = carMotion(13);
  m.waves[3].push_back({1.0, 2.0 * M_PI / 1100.0, 0.3});
  m.waves[4].push_back({0.8, 2.0 * M_PI / 700.0, 1.1});
  return m;
}

// A 3-mg wander on the accelerometer channels only.
const Eigen::Matrix<double, 6, 1> kAccelWander =
    (Eigen::Matrix<double, 6, 1>() << 0.0, 0.0, 0.0, 3e-2, 3e-2, 3e-2).finished();

// RMS over records of (fitted - true) / stated sigma of term t's first `axes` parameters, fitted
// alone (with the nuisance) under each of `options`, on the residuals make(seed) for seeds in
// [seed_begin, seed_end): one value per options entry.
template <typename MakeResidual>
std::vector<double> rmsErrOverSigma(const std::vector<CandidateTerm>& terms, int t,
                                    const Eigen::VectorXd& truth, int axes,
                                    const std::vector<SelectionOptions>& options,
                                    uint64_t seed_begin, uint64_t seed_end, MakeResidual make) {
  std::vector<double> z2(options.size(), 0.0);
  int count = 0;
  for (uint64_t seed = seed_begin; seed < seed_end; ++seed) {
    const Eigen::MatrixXd r = make(seed);
    for (std::size_t o = 0; o < options.size(); ++o) {
      const TermFit fit = fitTerms(r, terms, {t}, options[o]).selected.at(0);
      for (int a = 0; a < axes; ++a) z2[o] += std::pow((fit.theta(a) - truth(a)) / fit.sigma(a), 2);
    }
    count += axes;
  }
  for (double& v : z2) v = std::sqrt(v / count);
  return z2;
}

// A slowly wandering bias difference (two Gauss-Markov realizations, tau 20 min) on top of the
// white noise: without the slow-noise inflation, a temperature ramp regressor soaks it up and is
// claimed at hundreds of BIC units; with it, the slow candidates stay unclaimed on most records.
TEST(MismatchSelection, SlowBiasWanderIsNotClaimedAsTemperature) {
  const Motion m = carMotion(8);
  const RegressorInputs in = syntheticInputs(m, 600.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  SelectionOptions opt;
  opt.slow_block_bins = static_cast<int>(60.0 / in.reference.grid.bin_s);
  int claimed_temperature = 0;
  std::string log;
  for (uint64_t seed = 300; seed < 310; ++seed) {
    Eigen::MatrixXd r = ar1Noise(n, 0.3, seed);
    Eigen::Matrix<double, 6, 1> sd;  // wander 1-sigma per channel
    sd << 3e-4, 3e-4, 3e-4, 1e-2, 1e-2, 1e-2;
    addGaussMarkovWander(&r, sd, in.reference.grid.bin_s, 1200.0, seed + 1000);
    const SelectionResult sel = selectTerms(r, terms, opt);
    for (const TermFit& tf : sel.selected)
      if (tf.claimed && (terms[tf.term].kind() == TermKind::temperature_bias ||
                         terms[tf.term].kind() == TermKind::temperature_scale)) {
        ++claimed_temperature;
        log += terms[tf.term].key().text() + " ";
      }
  }
  EXPECT_LE(claimed_temperature, 1) << log;
}

// The 15-min slow drive the slow-noise tests share: its candidate library, the selection
// options with 60-s slow-noise blocks, and the index of the term under test (-1 if absent).
struct SlowDrive {
  RegressorInputs in;
  std::vector<CandidateTerm> terms;
  int n = 0;
  double bin_s = 0.0;
  SelectionOptions opt;
  int t = -1;
};

SlowDrive slowDrive(const TermKey& term_key) {
  SlowDrive d;
  d.in = syntheticInputs(slowDriveMotion(), 900.0, 0.0);
  d.terms = buildCandidateLibrary(d.in);
  d.n = d.in.reference.size();
  d.bin_s = d.in.reference.grid.bin_s;
  d.opt.slow_block_bins = static_cast<int>(60.0 / d.bin_s);
  d.t = findTerm(d.terms, term_key);
  return d;
}

// A fast term under a slow bias wander (Gauss-Markov, tau 20 min, ~3 mg): its GLS sigma is
// calibrated (RMS err/sigma near 1 over seeds: 0.89), where the white fit is off by 8.8 sigma
// RMS (its errors are ~5x larger and its sigma does not know the wander). The accelerometer scale factor's f_x / f_y columns follow the drive's acceleration
// pattern, here with minutes-long parts.
TEST(MismatchSelection, FastTermSigmaIsCalibratedUnderBiasWander) {
  const SlowDrive sd = slowDrive(termKey(TermKind::scale_factor, SensorScope::accel));
  ASSERT_GE(sd.t, 0);
  const std::vector<CandidateTerm>& terms = sd.terms;
  const int n = sd.n, t = sd.t;
  SelectionOptions opt = sd.opt;
  SelectionOptions white = opt;
  white.slow_block_bins = 0;
  const Eigen::Vector3d k(2e-3, -1.5e-3, 0.0);
  const auto residual = [&](uint64_t seed) {
    Eigen::MatrixXd r = ar1Noise(n, 0.3, seed) + termContribution(terms[t], k, n);
    addGaussMarkovWander(&r, kAccelWander, sd.bin_s, 1200.0, seed + 5000);
    return r;
  };
  const std::vector<double> rms = rmsErrOverSigma(terms, t, k, 2, {opt, white}, 700, 720, residual);
  EXPECT_GT(rms[0], 0.6);
  EXPECT_LT(rms[0], 1.5);
  EXPECT_GT(rms[1], 2.0 * rms[0]) << "the wander should matter on this motion";
}

// A fast term whose regressor lives on the wander's scales (white noise smoothed over 20 s)
// under a random walk on top of white noise (c_j about 13 at the 60-s level, as a MEMS
// accelerometer's two bias realizations give): a random walk's Haar coefficients are correlated
// across levels, so the level-diagonal GLS variance is short (RMS err/sigma 1.63 over 40
// records); the sandwich with the random walk of the law's 4^j part nearly calibrated (1.12).
TEST(MismatchSelection, SandwichCoversTheRandomWalkAcrossHaarLevels) {
  const int n = 18000;  // 15 min of 0.05-s bins
  std::vector<CandidateTerm> terms(2);
  terms[0] = constantNuisance(n);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  {
    StandardNormalSampler rng(4242);
    Eigen::VectorXd e(n);
    for (int i = 0; i < n; ++i) e(i) = rng.next();
    const int half = 1200;  // Gaussian kernel, sd 400 bins (20 s)
    for (int i = 0; i < n; ++i)
      for (int k = std::max(0, i - half); k <= std::min(n - 1, i + half); ++k)
        u(i) += std::exp(-0.5 * std::pow((k - i) / 400.0, 2)) * e(k);
    u /= std::sqrt((u.array() - u.mean()).square().mean());
  }
  terms[1] = CandidateTerm(termSpec(TermKind::scale_factor), SensorScope::accel);
  RegressorColumn col;
  col.channel[3] = u;
  terms[1].columns.push_back(col);
  const Eigen::VectorXd truth = Eigen::VectorXd::Constant(1, 0.05);
  const auto residual = [&](uint64_t seed) {
    StandardNormalSampler rng(seed);
    Eigen::MatrixXd r(n, 6);
    double walk = 0.0;
    for (int i = 0; i < n; ++i) {
      walk += 0.012 * rng.next();
      for (int c = 0; c < 6; ++c) r(i, c) = rng.next();
      r(i, 3) += walk + truth(0) * u(i);
    }
    return r;
  };
  SelectionOptions level_diagonal;
  level_diagonal.slow_block_bins = 1200;
  level_diagonal.random_walk_sandwich = false;
  SelectionOptions sandwich = level_diagonal;
  sandwich.random_walk_sandwich = true;
  const std::vector<double> rms =
      rmsErrOverSigma(terms, 1, truth, 1, {level_diagonal, sandwich}, 900, 940, residual);
  EXPECT_GT(rms[0], 1.25) << "the level-diagonal sigma should be short here";
  EXPECT_GT(rms[1], 0.75);
  EXPECT_LT(rms[1], 1.2);
}

// The stated covariance takes each variance from the larger of the two noise models and keeps
// the level-diagonal correlations: a parameter the sandwich states more certain (a quiet
// residual's slow misfit taken for a random walk) keeps its level-diagonal sigma.
TEST(MismatchSelection, AtLeastTheVariancesKeepsTheLargerVarianceAndTheCorrelation) {
  Eigen::Matrix2d P;
  P << 4.0, 1.2, 1.2, 1.0;  // correlation 0.6
  Eigen::Matrix2d Q;
  Q << 1.0, 0.0, 0.0, 9.0;
  const Eigen::MatrixXd out = atLeastTheVariances(P, Q);
  EXPECT_DOUBLE_EQ(out(0, 0), 4.0);
  EXPECT_DOUBLE_EQ(out(1, 1), 9.0);
  EXPECT_NEAR(out(0, 1) / std::sqrt(out(0, 0) * out(1, 1)), 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(out(0, 1), out(1, 0));
  EXPECT_THROW(atLeastTheVariances(P, Eigen::Matrix3d::Identity()), std::invalid_argument);
}

// A slow term under a slow bias wander: an accelerometer warm-up (12 degC over a 150-s time
// constant, 2-3 mg) next to a 3-mg Gauss-Markov wander (tau 20 min, two realizations' worth) over
// 15 minutes. Its stated sigma must cover its error: RMS err/sigma over 20 records within
// [0.5, 1.6] (0.87). With the block-mean factor alone (60-s blocks taken as independent) it was 2.27:
// the wander's projection onto the warm-up lives beyond one block (block_random_walk.h).
TEST(MismatchSelection, SlowTermSigmaCoversTheBiasWander) {
  const SlowDrive sd = slowDrive(termKey(TermKind::temperature_bias, SensorScope::accel));
  ASSERT_GE(sd.t, 0);
  const std::vector<CandidateTerm>& terms = sd.terms;
  const int n = sd.n, t = sd.t;
  SelectionOptions opt = sd.opt;
  const Eigen::Vector3d per_degC(2e-3, -1.5e-3, 2.5e-3);
  const auto residual = [&](uint64_t seed) {
    Eigen::MatrixXd r = ar1Noise(n, 0.3, seed) + termContribution(terms[t], per_degC, n);
    addGaussMarkovWander(&r, kAccelWander, sd.bin_s, 1200.0, seed + 7000);
    return r;
  };
  const double rms = rmsErrOverSigma(terms, t, per_degC, 3, {opt}, 900, 920, residual).at(0);
  EXPECT_GT(rms, 0.5);
  EXPECT_LT(rms, 1.6);
}

// The same with SG#2's two realizations: the field's wander and the lab's, replayed from a 600-s
// static record forward and backward (grafting.h). Told the replay (replay_period_s), the random
// walk holds it as a bounded replay: RMS err/sigma within [0.5, 1.6] (0.85). Taken for a second
// walk over the whole record it overstates the noise on the warm-up a little (0.80, same
// records).
TEST(MismatchSelection, SlowTermSigmaWithTheLabRecordReplayed) {
  const SlowDrive sd = slowDrive(termKey(TermKind::temperature_bias, SensorScope::accel));
  ASSERT_GE(sd.t, 0);
  const std::vector<CandidateTerm>& terms = sd.terms;
  const int n = sd.n, t = sd.t;
  SelectionOptions opt = sd.opt;
  const double bin_s = sd.bin_s;
  opt.bin_s = bin_s;
  SelectionOptions told = opt;
  told.replay_period_s = 600.0;
  told.replay_start_s = 0.0;
  const Eigen::Vector3d per_degC(2e-3, -1.5e-3, 2.5e-3);
  const int record = static_cast<int>(told.replay_period_s / bin_s);
  const auto residual = [&](uint64_t seed) {
    Eigen::MatrixXd r = ar1Noise(n, 0.3, seed) + termContribution(terms[t], per_degC, n);
    addGaussMarkovWander(&r, kAccelWander / std::sqrt(2.0), bin_s, 1200.0, seed + 8000);
    Eigen::MatrixXd lab = Eigen::MatrixXd::Zero(record, 6);
    addGaussMarkovWander(&lab, kAccelWander / std::sqrt(2.0), bin_s, 1200.0, seed + 9000);
    for (int i = 0; i < n; ++i) {  // the replay, subtracted as SG#2's own wander
      const int tile = i / record, k = i % record;
      r.row(i) -= lab.row(tile % 2 == 0 ? k : record - 1 - k);
    }
    return r;
  };
  const std::vector<double> rms =
      rmsErrOverSigma(terms, t, per_degC, 3, {told, opt}, 950, 970, residual);
  EXPECT_GT(rms[0], 0.5);
  EXPECT_LT(rms[0], 1.6);
  EXPECT_LT(rms[1], rms[0]);
}

// Cross-validation in the metric of the fit. A fast term whose regressor follows the drive's
// minutes-long speed-up and slow-down, at 3 x its detection limit under a slow bias wander
// (Gauss-Markov, tau 20 min, 3 mg): its GLS evidence is large, but in the AR(1) metric each
// fold's prediction error is dominated by the wander of its minutes and CV rejected it (random
// case random_11_16: a vibration level at 3.3 x its limit, delta_bic 414, cv_gain -0.002). With
// each fold's rows Haar-weighted like the fit, it is claimed in 10 of 10 records (6 of 10 with the
// AR(1) metric); on the wander alone nothing is.
TEST(MismatchSelection, CrossValidationInTheGlsMetricUnderBiasWander) {
  const SlowDrive sd = slowDrive(termKey(TermKind::scale_factor, SensorScope::accel));
  ASSERT_GE(sd.t, 0);
  const std::vector<CandidateTerm>& terms = sd.terms;
  const int n = sd.n, t = sd.t;
  SelectionOptions opt = sd.opt;
  const auto wander = [&](uint64_t seed) {
    Eigen::MatrixXd r = ar1Noise(n, 0.3, seed);
    addGaussMarkovWander(&r, kAccelWander, sd.bin_s, 1200.0, seed + 5000);
    return r;
  };
  double limit = 0.0;
  for (const TermLimit& l : selectTerms(wander(800), terms, opt).limits)
    if (l.term == t) limit = l.theta_limit(0);
  ASSERT_TRUE(std::isfinite(limit) && limit > 0.0);
  int found = 0, null_claims = 0;
  std::string log;
  for (uint64_t seed = 810; seed < 820; ++seed) {
    Eigen::VectorXd k = Eigen::VectorXd::Zero(3);
    k(0) = 3.0 * limit;
    const SelectionResult with =
        selectTerms(wander(seed) + termContribution(terms[t], k, n), terms, opt);
    for (const TermFit& tf : with.selected) found += tf.term == t && tf.claimed;
    const SelectionResult null = selectTerms(wander(seed), terms, opt);
    for (const TermFit& tf : null.selected)
      if (tf.claimed) {
        ++null_claims;
        log += terms[tf.term].key().text() + " ";
      }
  }
  EXPECT_GE(found, 9) << "limit " << limit;
  EXPECT_LE(null_claims, 1) << log;
}

// A term's slow-noise inflation is measured against the model it is tested in: once a
// temperature warm-up is claimed, its ramp is no longer "slow noise". Before, the warm-up stayed
// in the slow-noise residual, raised the gyro c_slow ~10-fold and cost a g-sensitivity (whose
// specific-force regressor has slow content) its detection (concealed gsens_temperature case).
TEST(MismatchSelection, ClaimedTemperatureDoesNotInflateOtherTerms) {
  const Motion m = carMotion(9);
  const RegressorInputs in = syntheticInputs(m, 1200.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  SelectionOptions opt;
  opt.slow_block_bins = static_cast<int>(60.0 / in.reference.grid.bin_s);
  const int g = findTerm(terms, termKey(TermKind::g_sensitivity, SensorScope::gyro)),
            tb = findTerm(terms, termKey(TermKind::temperature_bias, SensorScope::gyro));
  ASSERT_GE(g, 0);
  ASSERT_GE(tb, 0);
  Eigen::VectorXd G = Eigen::Map<const Eigen::VectorXd>(G9().data(), 9) * 0.25;
  const Eigen::MatrixXd r0 = termContribution(terms[g], G, n) + ar1Noise(n, 0.3, 21);
  const Eigen::MatrixXd r1 =
      r0 + termContribution(terms[tb], Eigen::Vector3d(1e-4, -1e-4, 8e-5), n);
  const SelectionResult alone = fitTerms(r0, terms, {g}, opt);
  const SelectionResult both = selectTerms(r1, terms, opt);
  const TermFit* g_fit = nullptr;
  bool temperature = false;
  for (const TermFit& tf : both.selected) {
    if (tf.term == g && tf.claimed) g_fit = &tf;
    temperature |= tf.term == tb && tf.claimed;
  }
  EXPECT_TRUE(temperature);
  ASSERT_NE(g_fit, nullptr) << "g_sensitivity missed next to a temperature warm-up";
  ASSERT_EQ(alone.selected.size(), 1u);
  EXPECT_LT(g_fit->inflation_factor, 1.2 * alone.selected[0].inflation_factor);
}

}  // namespace
}  // namespace graftnav
