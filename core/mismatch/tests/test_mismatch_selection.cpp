// Mismatch finder, selection: silence on coloured noise, detection limits, alternatives that do
// not cycle, and names next to a misalignment.
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

// The stated false-alarm rate: on pure coloured noise no term is claimed in at least 95 % of the
// records. 40 seeds; the binomial probability of more than 5 claims at a true 5 % rate is 0.05.
TEST(MismatchSelection, RejectsTermsOnColouredNoise) {
  const Motion m = carMotion(5);
  const RegressorInputs in = syntheticInputs(m, 200.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  int records_with_claims = 0;
  std::string claimed;
  for (uint64_t seed = 100; seed < 140; ++seed) {
    const double rho = 0.3 + 0.6 * ((seed * 37) % 10) / 10.0;
    const SelectionResult sel = selectTerms(ar1Noise(n, rho, seed), terms);
    if (!sel.selected.empty()) {
      ++records_with_claims;
      claimed += terms[sel.selected[0].term].key().text() + " ";
    }
  }
  RecordProperty("records_with_claims", records_with_claims);
  EXPECT_LE(records_with_claims, 5) << claimed;
}

// The detection limit reported for a candidate left out means what it says: injected at 2.5 times
// its limit (one parameter) the term is claimed on nearly every record, at 0.3 times almost never.
TEST(MismatchSelection, DetectionLimitSeparatesFoundFromMissed) {
  const Motion m = carMotion(5);
  const RegressorInputs in = syntheticInputs(m, 200.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  for (const TermKey& key : {termKey(TermKind::scale_factor, SensorScope::gyro),
                             termKey(TermKind::lever_arm, SensorScope::accel)}) {
    const int t = findTerm(terms, key);
    ASSERT_GE(t, 0) << key.text();
    const SelectionResult noise_only = selectTerms(ar1Noise(n, 0.3, 500), terms);
    double limit = 0.0;
    for (const TermLimit& l : noise_only.limits)
      if (l.term == t) limit = l.theta_limit(2);
    ASSERT_TRUE(std::isfinite(limit) && limit > 0.0) << key.text();
    for (const double factor : {2.5, 0.3}) {
      Eigen::VectorXd theta =
          Eigen::VectorXd::Zero(static_cast<Eigen::Index>(terms[t].columns.size()));
      theta(2) = factor * limit;
      int found = 0;
      for (uint64_t seed = 600; seed < 620; ++seed) {
        const Eigen::MatrixXd r = ar1Noise(n, 0.3, seed) + termContribution(terms[t], theta, n);
        for (const TermFit& tf : selectTerms(r, terms).selected)
          found += tf.term == t && tf.claimed;
      }
      if (factor > 1.0) {
        EXPECT_GE(found, 18) << key.text() << " at " << factor << " x its limit " << limit;
      } else {
        EXPECT_LE(found, 2) << key.text() << " at " << factor << " x its limit " << limit;
      }
    }
  }
}

// Two terms that replace each other (as the gyro's two vibration regressors do) and explain the
// residual equally well: backward elimination dropped one, which brought the other back, which
// failed in turn, for ever (a scale_asymmetry / scale_nonlinearity pair tried this way hung
// diagnose). The stepwise search must stop.
TEST(MismatchSelection, MutuallyExclusiveTermsOfEqualEvidenceDoNotCycle) {
  const int n = 4000;
  StandardNormalSampler rng(77);
  Eigen::VectorXd a(n), b(n);
  for (int i = 0; i < n; ++i) a(i) = std::sin(0.01 * i) + 0.3 * rng.next();
  b = a;  // identical evidence: each fails against the other by less than min_delta_bic
  std::vector<CandidateTerm> terms(3);
  terms[0] = constantNuisance(n);
  for (int k = 1; k <= 2; ++k) {
    const TermVariant level[2] = {TermVariant::specific_force_hp_sq,
                                  TermVariant::angular_rate_hp_sq};
    terms[k] =
        CandidateTerm(termSpec(TermKind::vibration_rectification), SensorScope::gyro, level[k - 1]);
    terms[k].excludes = {
        termKey(TermKind::vibration_rectification, SensorScope::gyro, level[2 - k])};
    RegressorColumn col;
    col.channel[0] = k == 1 ? a : b;
    terms[k].columns.push_back(col);
  }
  Eigen::MatrixXd r = 0.05 * ar1Noise(n, 0.0, 78);
  r.col(0) += 0.02 * a;
  const SelectionResult sel = selectTerms(r, terms);
  int chosen = 0;
  for (const TermFit& tf : sel.selected) chosen += tf.term == 1 || tf.term == 2;
  EXPECT_EQ(chosen, 1) << ::testing::PrintToString(sel.log);  // present, named once
}

// A g-sensitivity next to a mounting misalignment on car-like motion, where the lateral specific
// force is v omega_z (so G f_y shares its signal with omega x phi and the gyro non-orthogonality)
// and f_z ~ -g is nearly the constant bias: the evidence counts G's f_z directions by the
// information they carry (header, step 2), and the stepwise search lets G in once a
// non-orthogonality that absorbed part of it is dropped. G is 0.14 x G9 (1.4-4.2e-5 rad/s per m/s^2);
// found on 10 of these 10 seeds, on 7 with the plain BIC penalty p ln(N / c) and the same stepwise
// search (0.12 x G9: 5 and 0 of 10); nothing else claimed. On the same motion with the
// misalignment alone or pure noise, 0 of 60 seeds claimed anything under either rule.
TEST(MismatchSelection, GSensitivityNextToMisalignmentOnCarMotion) {
  Motion m = carMotion(12);
  const double v_m_s = 15.0;
  m.waves[4].clear();  // lateral specific force = v omega_z, plus a little of its own
  for (const Wave& w : m.waves[2]) m.waves[4].push_back({v_m_s * w.amp, w.omega, w.phase});
  m.waves[4].push_back({0.1, 2.0 * M_PI * 0.3, 0.4});
  for (Wave& w : m.waves[5]) w.amp *= 0.1;  // vertical: road undulation only, f_z ~ -g
  const RegressorInputs in = syntheticInputs(m, 900.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  const int g = findTerm(terms, termKey(TermKind::g_sensitivity, SensorScope::gyro));
  const int mis = findTerm(terms, termKey(TermKind::mounting_misalignment, SensorScope::both));
  ASSERT_GE(g, 0);
  ASSERT_GE(mis, 0);
  const Eigen::VectorXd G = Eigen::Map<const Eigen::VectorXd>(G9().data(), 9) * 0.14;
  const Eigen::Vector3d phi(-3.5e-3, 2.6e-3, 1.7e-3);
  const Eigen::MatrixXd signal =
      termContribution(terms[g], G, n) + termContribution(terms[mis], phi, n);
  int found = 0, other = 0;
  std::string log;
  for (uint64_t seed = 500; seed < 510; ++seed) {
    const SelectionResult sel = selectTerms(signal + ar1Noise(n, 0.3, seed), terms);
    for (const TermFit& tf : sel.selected) {
      if (!tf.claimed) continue;
      if (tf.term == g) {
        ++found;
        for (int j = 0; j < 9; ++j)
          EXPECT_LT(std::abs(tf.theta(j) - G(j)), 3.5 * tf.sigma(j))
              << "seed " << seed << " G " << j;
      } else if (tf.term != mis) {
        ++other;
        log += terms[tf.term].key().text() + " ";
      }
    }
  }
  EXPECT_GE(found, 9);
  EXPECT_EQ(other, 0) << log;
}

// A mounting rotation next to cross-axis errors of both triads (the accelerometer's symmetric,
// as the accelerometer triad defines the body frame). Both full non-orthogonalities together
// span the rotation, so once both were in, the misalignment had no evidence left and was
// dropped: one physical rotation came back as two cross-axis matrices (wid_car_trial07). The
// gauge step names it as the rotation again, with the accelerometer's symmetric part.
TEST(MismatchSelection, RotationNextToBothNonOrthogonalitiesKeepsItsName) {
  const Motion m = carMotion(9);
  const RegressorInputs in = syntheticInputs(m, 600.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  const int mis = findTerm(terms, termKey(TermKind::mounting_misalignment, SensorScope::both));
  const int ng = findTerm(terms, termKey(TermKind::non_orthogonality, SensorScope::gyro));
  const int na = findTerm(terms, termKey(TermKind::non_orthogonality, SensorScope::accel));
  ASSERT_GE(mis, 0);
  ASSERT_GE(ng, 0);
  ASSERT_GE(na, 0);
  const Eigen::Vector3d phi(0.02, -0.03, 0.05);
  Eigen::VectorXd Ng(6), Na(6);  // off-diagonal elements in row order (01, 02, 10, 12, 20, 21)
  Ng << 4e-3, -3e-3, 1e-3, 5e-3, -2e-3, 3e-3;
  Na << 6e-3, -4e-3, 6e-3, 3e-3, -4e-3, 3e-3;  // symmetric: N_ij = N_ji
  const Eigen::MatrixXd r = termContribution(terms[mis], phi, n) +
                            termContribution(terms[ng], Ng, n) +
                            termContribution(terms[na], Na, n) + ar1Noise(n, 0.5, 31);
  const SelectionResult sel = selectTerms(r, terms);
  const TermFit* rot = nullptr;
  const TermFit* acc = nullptr;
  for (const TermFit& tf : sel.selected) {
    if (tf.term == mis) rot = &tf;
    if (terms[tf.term].kind() == TermKind::non_orthogonality &&
        terms[tf.term].sensor == SensorScope::accel)
      acc = &tf;
  }
  ASSERT_NE(rot, nullptr) << ::testing::PrintToString(sel.log);
  EXPECT_TRUE(rot->claimed);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(rot->theta(a), phi(a), 3.5 * rot->sigma(a)) << "axis " << a;
  ASSERT_NE(acc, nullptr) << ::testing::PrintToString(sel.log);
  EXPECT_EQ(terms[acc->term].variant, TermVariant::symmetric);
  const double sym[3] = {Na(0), Na(1), Na(3)};  // pairs 01, 02, 12
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(acc->theta(k), sym[k], 3.5 * acc->sigma(k)) << "pair " << k;
}

}  // namespace
}  // namespace graftnav
