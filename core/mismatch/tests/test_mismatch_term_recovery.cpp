// Mismatch finder, candidate terms: each term recovers its injected parameters within its stated
// uncertainty, the quadratic is measured beyond its linear term, and the rotation's columns at a
// pivot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "graftnav/eval/evaluation.h"
#include "graftnav/imu/gauss_markov.h"
#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/mismatch/time_offset.h"
#include "graftnav/nav/rotation.h"
#include "synthetic_imu.h"
#include "mismatch_signal_fixture.h"

namespace graftnav {
namespace {

using namespace mismatch_test;  // the shared fixtures of mismatch_signal_fixture.h

struct Injection {
  TermKey key;
  std::vector<double> theta;
  double noise_scale = 1.0;  // relative to the MEMS-like AR(1) noise of ar1Noise
};

class MismatchTermRecovery : public ::testing::TestWithParam<Injection> {};

TEST_P(MismatchTermRecovery, RecoversInjectedParametersWithinStatedUncertainty) {
  const Injection inj = GetParam();
  const Motion m = carMotion(7);
  const RegressorInputs in = syntheticInputs(m, 300.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int t = findTerm(terms, inj.key);
  ASSERT_GE(t, 0) << inj.key.text();
  const int n = in.reference.size();
  Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(inj.theta.data(), inj.theta.size());
  if (terms[t].fixed()) theta = Eigen::VectorXd::Ones(terms[t].columns.size());
  ASSERT_EQ(theta.size(), static_cast<Eigen::Index>(terms[t].columns.size())) << inj.key.text();
  Eigen::MatrixXd r = termContribution(terms[t], theta, n) + inj.noise_scale * ar1Noise(n, 0.6, 11);
  r.col(0).array() += 1e-3;  // turn-on bias: the nuisance
  r.col(5).array() -= 0.05;

  // The fit holds t and the terms t requires (e.g. the linear term next to a quadratic).
  const SelectionResult fit = fitTerms(r, terms, {t});
  ASSERT_EQ(fit.selected.size(), 1u + terms[t].requires_terms.size()) << inj.key.text();
  const auto it = std::find_if(fit.selected.begin(), fit.selected.end(),
                               [&](const TermFit& f) { return f.term == t; });
  ASSERT_NE(it, fit.selected.end()) << inj.key.text();
  const TermFit& tf = *it;
  for (const TermFit& f : fit.selected) {
    if (f.term != t) {
      EXPECT_NE(std::find(terms[t].requires_terms.begin(), terms[t].requires_terms.end(),
                          terms[f.term].key()),
                terms[t].requires_terms.end())
          << terms[f.term].key().text();
    }
  }
  if (!terms[t].fixed()) {
    const Eigen::VectorXd err = tf.theta - theta;
    // Parameters without signal (e.g. k_pos of an axis whose input is never positive) come back
    // as 0 with infinite sigma; the rest must be consistent with their covariance.
    std::vector<int> obs;
    for (Eigen::Index j = 0; j < err.size(); ++j)
      if (std::isfinite(tf.sigma(j))) obs.push_back(static_cast<int>(j));
    ASSERT_FALSE(obs.empty());
    Eigen::VectorXd e(obs.size());
    Eigen::MatrixXd P(obs.size(), obs.size());
    for (std::size_t a = 0; a < obs.size(); ++a) {
      e(a) = err(obs[a]);
      for (std::size_t b = 0; b < obs.size(); ++b) P(a, b) = tf.covariance(obs[a], obs[b]);
    }
    const double chi2 = e.dot(P.ldlt().solve(e));
    EXPECT_LT(chi2, chiSquareQuantile(0.999, static_cast<double>(e.size()))) << inj.key.text();
    for (int j : obs)
      EXPECT_LT(std::abs(err(j)), 3.5 * tf.sigma(j)) << inj.key.text() << " param " << j;
  }
  EXPECT_GT(tf.delta_bic, 10.0) << inj.key.text();
  EXPECT_GT(tf.cv_gain, 0.0) << inj.key.text();

  // Selection from the whole library claims this term and at most one other.
  const SelectionResult sel = selectTerms(r, terms);
  bool found = false;
  std::size_t claimed = 0;
  for (const TermFit& s : sel.selected) {
    found |= s.term == t && s.claimed;
    claimed += s.claimed ? 1 : 0;
  }
  EXPECT_TRUE(found) << inj.key.text();
  EXPECT_LE(claimed, 2u) << inj.key.text();
}

INSTANTIATE_TEST_SUITE_P(
    AllTerms, MismatchTermRecovery,
    ::testing::Values(
        Injection{termKey(TermKind::scale_factor, SensorScope::gyro), {3e-3, -2e-3, 1e-2}},
        Injection{termKey(TermKind::scale_factor, SensorScope::accel), {5e-3, -4e-3, 2e-2}},
        Injection{termKey(TermKind::non_orthogonality, SensorScope::gyro),
                  {2e-2, -1e-2, 5e-3, 3e-3, -4e-3, 2e-3}},
        Injection{termKey(TermKind::non_orthogonality, SensorScope::accel),
                  {3e-3, -2e-3, 4e-3, 3e-3, -2e-3, 2e-3}},
        Injection{termKey(TermKind::g_sensitivity, SensorScope::gyro), G9()},
        Injection{termKey(TermKind::scale_asymmetry, SensorScope::gyro), {3e-2, -2e-2, 2e-2}},
        Injection{termKey(TermKind::scale_asymmetry, SensorScope::accel), {2e-2, 1e-2, -1e-2}},
        Injection{termKey(TermKind::scale_nonlinearity, SensorScope::gyro), {0.5, -0.5, 0.1}},
        Injection{termKey(TermKind::scale_nonlinearity, SensorScope::accel), {2e-3, -2e-3, 1e-3}},
        Injection{termKey(TermKind::temperature_bias, SensorScope::gyro), {1e-4, -2e-4, 1e-4}},
        Injection{termKey(TermKind::temperature_bias, SensorScope::accel), {2e-3, -1e-3, 3e-3}},
        Injection{termKey(TermKind::temperature_scale, SensorScope::gyro), {1e-3, -1e-3, 5e-4}},
        Injection{termKey(TermKind::temperature_scale, SensorScope::accel), {5e-4, -5e-4, 5e-4}},
        Injection{termKey(TermKind::time_offset, SensorScope::both), {0.012}},
        Injection{termKey(TermKind::lever_arm, SensorScope::accel), {0.4, -0.3, 0.2}},
        Injection{termKey(TermKind::mounting_misalignment, SensorScope::both), {0.01, -0.01, 0.02}},
        Injection{termKey(TermKind::vibration_rectification, SensorScope::accel,
                          TermVariant::specific_force_hp_sq),
                  {0.02, -0.03, 0.02}},
        Injection{termKey(TermKind::vibration_rectification, SensorScope::gyro,
                          TermVariant::specific_force_hp_sq),
                  {2e-3, -2e-3, 3e-3}},
        Injection{termKey(TermKind::vibration_rectification, SensorScope::gyro,
                          TermVariant::angular_rate_hp_sq),
                  {0.5, 0.3, -0.4}},
        Injection{termKey(TermKind::earth_rotation_omitted, SensorScope::gyro), {}, 0.01},
        // Tested against a wandering accel bias (requires_terms): needs a quieter (tactical) IMU.
        Injection{termKey(TermKind::gravity_model, SensorScope::accel), {0.05}, 0.1}),
    [](const ::testing::TestParamInfo<Injection>& param_info) {
      std::string s = param_info.param.key.text();
      for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return s;
    });

// Marginality: under gravity f_z keeps one sign around -g, so (f_z)^2 = -2 g f_z - g^2 +
// (f_z + g)^2 imitates a z scale factor. The quadratic is measured, and fitted, with the
// linear term in the model: a pure z scale factor is not named a non-linearity, and the linear
// companion carries it (without the rule, fitTerms gave x^2 alone a delta_bic of 2226 here).
TEST(MismatchSelection, QuadraticIsMeasuredBeyondItsLinearTerm) {
  const Motion m = carMotion(13);
  const RegressorInputs in = syntheticInputs(m, 300.0, 0.0);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int n = in.reference.size();
  const int t_nl = findTerm(terms, termKey(TermKind::scale_nonlinearity, SensorScope::accel));
  const int t_sf = findTerm(terms, termKey(TermKind::scale_factor, SensorScope::accel));
  ASSERT_GE(t_nl, 0);
  ASSERT_GE(t_sf, 0);
  const Eigen::Vector3d k(0.0, 0.0, 3e-2);
  Eigen::MatrixXd r = termContribution(terms[t_sf], k, n) + ar1Noise(n, 0.6, 17);

  const SelectionResult fit = fitTerms(r, terms, {t_nl});
  const TermFit* nl = nullptr;
  const TermFit* sf = nullptr;
  for (const TermFit& f : fit.selected) {
    if (f.term == t_nl) nl = &f;
    if (f.term == t_sf) sf = &f;
  }
  ASSERT_NE(nl, nullptr);
  ASSERT_NE(sf, nullptr) << "the quadratic was fitted without its linear term";
  EXPECT_FALSE(nl->claimed) << "delta_bic " << nl->delta_bic;
  EXPECT_LT(nl->delta_bic, 6.0);
  for (int a = 0; a < 3; ++a) {
    if (std::isfinite(nl->sigma(a))) {
      EXPECT_LT(std::abs(nl->theta(a)), 3.5 * nl->sigma(a)) << a;
    }
    EXPECT_LT(std::abs(sf->theta(a) - k(a)), 3.5 * sf->sigma(a)) << a;
  }

  const SelectionResult sel = selectTerms(r, terms);
  bool scale_claimed = false;
  for (const TermFit& f : sel.selected) {
    EXPECT_FALSE(f.term == t_nl && f.claimed) << "scale_nonlinearity claimed for a scale factor";
    scale_claimed |= f.term == t_sf && f.claimed;
  }
  EXPECT_TRUE(scale_claimed);
}

// mounting_misalignment linearized at a pivot: its columns are the exact rotation's Jacobian
// there (checked against central differences of C_tb(phi) x), and columns plus the fixed
// remainder reproduce C_tb(phi) x - x exactly at the pivot and to second order in phi - phi0
// around it, where the first-order columns miss by |phi|^2 / 2 of the signal.
TEST(MismatchRotation, LinearizedAtItsPivot) {
  const Motion m = carMotion(3);
  RegressorInputs in = syntheticInputs(m, 60.0, 0.0);
  const Eigen::Vector3d phi0(-0.056, 0.022, 0.080);  // 5.6 deg (a real recording's size)
  in.mounting_rotation_pivot_rad = phi0;
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in);
  const int t_rot = findTerm(terms, termKey(TermKind::mounting_misalignment, SensorScope::both));
  const int t_rem =
      findTerm(terms, termKey(TermKind::mounting_rotation_remainder, SensorScope::both));
  ASSERT_GE(t_rot, 0);
  ASSERT_GE(t_rem, 0);
  EXPECT_TRUE(terms[t_rem].fixed());
  EXPECT_EQ(terms[t_rem].part_of, terms[t_rot].key());
  ASSERT_EQ(terms[t_rot].requires_terms.size(), 1u);
  const int n = in.reference.size();
  const auto exact = [&](const Eigen::Vector3d& phi) {  // C_tb(phi) x - x, n x 6
    const Eigen::Matrix3d C = dcmFromRotationVector(phi).transpose();
    Eigen::MatrixXd out(n, 6);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d w = in.reference.omega_rad_s.row(i).transpose();
      const Eigen::Vector3d f = in.reference.f_m_s2.row(i).transpose();
      out.row(i) << (C * w - w).transpose(), (C * f - f).transpose();
    }
    return out;
  };
  const auto model = [&](const Eigen::Vector3d& phi) {
    return (termContribution(terms[t_rot], phi, n) +
            termContribution(terms[t_rem], Eigen::VectorXd::Ones(1), n))
        .eval();
  };
  const double scale = exact(phi0).cwiseAbs().maxCoeff();
  EXPECT_LT((model(phi0) - exact(phi0)).cwiseAbs().maxCoeff(), 1e-12 * std::max(scale, 1.0));
  const double h = 1e-6;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(j);
    const Eigen::MatrixXd numeric = (exact(phi0 + h * e) - exact(phi0 - h * e)) / (2.0 * h);
    const Eigen::MatrixXd analytic = termContribution(terms[t_rot], e, n);
    EXPECT_LT((numeric - analytic).cwiseAbs().maxCoeff(),
              1e-7 * numeric.cwiseAbs().maxCoeff() + 1e-9)
        << "column " << j;
  }
  const Eigen::Vector3d dphi(2e-3, -1e-3, 1.5e-3);
  const double err_pivot = (model(phi0 + dphi) - exact(phi0 + dphi)).cwiseAbs().maxCoeff();
  EXPECT_LT(err_pivot, 2.0 * dphi.squaredNorm() * scale / phi0.norm());
  // The first-order columns (pivot 0) miss by about |phi|^2 / 2 of the signal.
  in.mounting_rotation_pivot_rad.setZero();
  const std::vector<CandidateTerm> flat = buildCandidateLibrary(in);
  const int t_flat = findTerm(flat, termKey(TermKind::mounting_misalignment, SensorScope::both));
  EXPECT_EQ(findTerm(flat, termKey(TermKind::mounting_rotation_remainder, SensorScope::both)), -1);
  const double err_flat =
      (termContribution(flat[t_flat], phi0 + dphi, n) - exact(phi0 + dphi)).cwiseAbs().maxCoeff();
  EXPECT_GT(err_flat, 50.0 * err_pivot);
}

}  // namespace
}  // namespace graftnav
