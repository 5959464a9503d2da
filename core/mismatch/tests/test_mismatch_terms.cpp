// Mismatch finder, signal level: common grid, time offset, candidate terms recover their own
// parameters, and the selection stays silent on coloured noise.
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

namespace graftnav {
namespace {

// Car-like analytic motion: each channel a sum of sinusoids, integrated exactly over samples.
struct Wave {
  double amp, omega, phase;
};
struct Motion {
  std::array<std::vector<Wave>, 6> waves;
  Vector6d offset = Vector6d::Zero();
  Vector6d integral(double t) const {  // integral from 0 to t
    Vector6d out = offset * t;
    for (int c = 0; c < 6; ++c)
      for (const Wave& w : waves[c])
        out(c) += w.amp / w.omega * (std::cos(w.phase) - std::cos(w.omega * t + w.phase));
    return out;
  }
};

Motion carMotion(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Motion m;
  const double amp[6] = {0.05, 0.05, 0.25, 1.5, 2.0, 0.6};
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k < 6; ++k)
      m.waves[c].push_back({amp[c] * (0.3 + U(rng)), 2.0 * M_PI * (0.005 + 0.4 * U(rng)),
                            2.0 * M_PI * U(rng)});
  m.offset << 0.0, 0.0, 0.0, 0.1, -0.2, -9.79;
  return m;
}

ImuSeries sampleMotion(const Motion& m, double rate_hz, double duration_s, double tau_s = 0.0,
                       double t0_s = 1000.0) {
  ImuSeries out;
  const int n = static_cast<int>(duration_s * rate_hz);
  for (int k = 1; k <= n; ++k) {
    const double t1 = k / rate_hz, t0 = (k - 1) / rate_hz;
    // Tags late by tau: the sample tagged t covers true time (t0 - tau, t1 - tau].
    const Vector6d inc = m.integral(t1 - tau_s) - m.integral(t0 - tau_s);
    ImuSample s;
    s.t_s = t0_s + t1;
    s.dt_s = 1.0 / rate_hz;
    s.dtheta_rad = inc.head<3>();
    s.dvel_m_s = inc.tail<3>();
    out.push_back(s);
  }
  return out;
}

TEST(MismatchGrid, BinsOfDifferentRatesAgree) {
  const Motion m = carMotion(1);
  const ImuSeries a = sampleMotion(m, 100.0, 60.0);
  const ImuSeries b = sampleMotion(m, 120.0, 60.0);
  const GridSpec g = commonGrid(a, b, 0.05);
  const BinnedImu ba = binImu(a, g), bb = binImu(b, g);
  // Exact integral over each bin from the analytic motion.
  double max_err = 0.0;
  for (int i = 0; i < g.count; ++i) {
    const Vector6d exact =
        (m.integral(g.binStart(i + 1) - 1000.0) - m.integral(g.binStart(i) - 1000.0)) / g.bin_s;
    max_err = std::max(max_err, (ba.row(i) - exact).cwiseAbs().maxCoeff());
    max_err = std::max(max_err, (bb.row(i) - exact).cwiseAbs().maxCoeff());
  }
  // Piecewise-constant rate inside a sample: error ~ rate change over half a sample.
  EXPECT_LT(max_err, 0.02);
  EXPECT_GT(g.count, 1100);
}

// Road and engine vibration reaches 40 Hz: a bin mean of a record shifted by a fraction of a
// sample keeps a 15-35 Hz component to 1e-3 of its amplitude (band-limited interpolation of the
// cumulative integral; the cubic Hermite curve alone lost 0.4 % at 15 Hz and 17 % at 30 Hz).
TEST(MismatchGrid, ShiftedBinMeansFollowVibration) {
  for (double f_hz : {15.0, 25.0, 35.0}) {
    Motion m;
    for (int c = 0; c < 6; ++c) m.waves[c].push_back({1.0, 2.0 * M_PI * f_hz, 0.4 * c});
    const ImuSeries imu = sampleMotion(m, 100.0, 30.0);
    const GridSpec g = commonGrid(imu, imu, 0.05, 1.0);
    const double shift = 0.0137;  // bin (a, b] of x(t + shift)
    const BinnedImu b = binImu(imu, g, shift);
    double max_err = 0.0;
    for (int i = 0; i < g.count; ++i) {
      const Vector6d exact = (m.integral(g.binStart(i + 1) + shift - 1000.0) -
                              m.integral(g.binStart(i) + shift - 1000.0)) / g.bin_s;
      max_err = std::max(max_err, (b.row(i) - exact).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(max_err, 1e-3) << f_hz << " Hz";
  }
}

// The gain of a shifted bin mean must hold to ~1 ppm where car motion has its energy: a
// scale factor is resolved to ~1 ppm when simulation and record share their noise, and a 32-tap
// beta-8 window (passband ripple ~1e-4) made a 3.1-Hz roll oscillation shifted by 4 ms 6.7e-5
// too large, which the finder named a -40..-60 ppm gyro scale factor next to every time offset.
TEST(MismatchGrid, ShiftedBinMeansKeepTheirGain) {
  for (double shift : {0.004, 0.0137}) {
    // 20 Hz is left out: a whole cycle per 0.05-s bin, its bin means vanish.
    for (double f_hz : {0.3, 1.0, 3.1, 5.0, 10.0, 30.0, 38.0, 42.0}) {
      Motion m;
      m.waves[0].push_back({1.0, 2.0 * M_PI * f_hz, 0.3});
      const ImuSeries imu = sampleMotion(m, 100.0, 300.0);
      const GridSpec g = commonGrid(imu, imu, 0.05, 1.0);
      const BinnedImu b = binImu(imu, g, shift);
      double err_sq = 0.0, exact_sq = 0.0;
      for (int i = 0; i < g.count; ++i) {
        const double exact = (m.integral(g.binStart(i + 1) + shift - 1000.0)(0) -
                              m.integral(g.binStart(i) + shift - 1000.0)(0)) / g.bin_s;
        err_sq += std::pow(b.omega_rad_s(i, 0) - exact, 2);
        exact_sq += exact * exact;
      }
      const double rel = std::sqrt(err_sq / exact_sq);
      EXPECT_LT(rel, f_hz <= 10.0 ? 5e-6 : 2e-5) << f_hz << " Hz, shift " << shift << " s";
    }
  }
}

TEST(MismatchTimeOffset, RecoveredAcrossSampleRates) {
  const Motion m = carMotion(2);
  const ImuSeries ref = sampleMotion(m, 100.0, 120.0);
  for (double tau : {0.0257, -0.0413, 0.0031}) {
    const ImuSeries tested = sampleMotion(m, 120.0, 120.0, tau);
    const TimeOffsetEstimate est = estimateTimeOffset(ref, tested);
    EXPECT_TRUE(est.reliable);
    EXPECT_NEAR(est.tau_s, tau, 1.5e-3) << "tau " << tau;
    // Re-aligning with the estimate makes the bins agree to the sampling error.
    const GridSpec g = commonGrid(ref, tested, 0.05, 0.5);
    const BinnedImu x = binImu(ref, g), y0 = binImu(tested, g), y1 = binImu(tested, g, est.tau_s);
    const double before = (y0.omega_rad_s - x.omega_rad_s).norm();
    const double after = (y1.omega_rad_s - x.omega_rad_s).norm();
    if (std::abs(tau) > 0.01) {
      EXPECT_LT(after, 0.2 * before);
    }
  }
}

// The lever arm's omega_dot regressor must hold the exact bin mean (omega(b) - omega(a)) / h of
// the angular acceleration at road-oscillation frequencies (2-5 Hz), for 100 and 120 Hz records:
// a one-bin centred window attenuated 3.1 Hz by 3.9 % and overstated r_m by that much (7.6
// sigma on the concealed lever_arm case).
TEST(MismatchLeverArm, AngularAccelerationBinMeansUnbiasedAtRoadFrequencies) {
  Motion m;
  const double freq_hz[3] = {2.3, 3.1, 4.2};
  for (int c = 0; c < 3; ++c) m.waves[c].push_back({0.01, 2.0 * M_PI * freq_hz[c], 0.7 * c});
  m.offset << 0.0, 0.0, 0.0, 0.0, 0.0, -9.8;
  for (double rate : {100.0, 120.0}) {
    const ImuSeries imu = sampleMotion(m, rate, 60.0);
    const GridSpec g = commonGrid(imu, imu, 0.05, 0.5);
    const Eigen::MatrixX3d wdot = angularAccelerationPerBin(imu, g).omega_dot_rad_s2;
    for (int c = 0; c < 3; ++c) {
      const Wave& w = m.waves[c][0];
      const auto omega = [&](double t) { return w.amp * std::sin(w.omega * (t - 1000.0) + w.phase); };
      double num = 0.0, den = 0.0;
      for (int i = 0; i < g.count; ++i) {
        const double exact = (omega(g.binStart(i + 1)) - omega(g.binStart(i))) / g.bin_s;
        num += exact * wdot(i, c);
        den += exact * exact;
      }
      // Gain of the regressor against the exact bin means: within 1 % up to 4.2 Hz (Richardson
      // residual 0.6 % there; the one-bin window lost 2.2 / 3.9 / 7 % at 2.3 / 3.1 / 4.2 Hz).
      EXPECT_NEAR(num / den, 1.0, 1e-2) << "axis " << c << " at " << freq_hz[c] << " Hz, " << rate
                                        << " Hz record";
    }
  }
}

// Road and engine vibration (8-40 Hz) is angular acceleration too, and at 100 Hz its top is 0.8 x
// Nyquist. With the edge-rate window held at the sample interval or longer (12.5 ms here) the
// Richardson gain 1 - 4 (pi f w)^4 / 120 + ... lost 3 / 8 / 12 % at 25 / 33 / 38 Hz, and the
// random cases with vibration came out with r_m 3-5 % short at 25-60 sigma. On a uniform record
// the cumulative integral is band limited between samples, so a noise-free reference may use
// windows down to a quarter sample.
TEST(MismatchLeverArm, AngularAccelerationBinMeansFollowVibrationNearNyquist) {
  // 10 s at rest (where the reference's noise is measured), then vibration that starts at zero
  // rate: omega_c(t) = A sin(2 pi f_c (t - 10)).
  const double freq_hz[3] = {25.0, 33.0, 38.0}, amp = 0.02, t_start = 10.0, t0 = 1000.0;
  const auto integral = [&](double t) {
    Vector6d out = Vector6d::Zero();
    out(5) = -9.8 * t;
    if (t > t_start)
      for (int c = 0; c < 3; ++c) {
        const double w = 2.0 * M_PI * freq_hz[c];
        out(c) = amp / w * (1.0 - std::cos(w * (t - t_start)));
      }
    return out;
  };
  const ImuSeries imu = test::sampleIntegral(integral, 100.0, 40.0, t0);
  const GridSpec g = commonGrid(imu, imu, 0.05, 0.5);
  const AngularAccelerationBins wdot = angularAccelerationPerBin(imu, g);
  for (int c = 0; c < 3; ++c) {
    const double w = 2.0 * M_PI * freq_hz[c];
    const auto omega = [&](double t) { return amp * std::sin(w * (t - t0 - t_start)); };
    double num = 0.0, den = 0.0;
    for (int i = 0; i < g.count; ++i) {
      if (g.binStart(i) < t0 + t_start + 1.0) continue;
      const double exact = (omega(g.binStart(i + 1)) - omega(g.binStart(i))) / g.bin_s;
      num += exact * wdot.omega_dot_rad_s2(i, c);
      den += exact * exact;
    }
    EXPECT_NEAR(num / den, 1.0, 1e-2) << "axis " << c << " at " << freq_hz[c] << " Hz (window "
                                      << wdot.window_s(c) << " s)";
  }
}

// Regressor inputs from the analytic motion, with temperature, vibration level and attitude.
RegressorInputs syntheticInputs(const Motion& m, double duration_s, double pivot_s) {
  const ImuSeries ref = sampleMotion(m, 100.0, duration_s);
  const GridSpec g = commonGrid(ref, ref, 0.05);
  RegressorInputs in;
  in.reference = binImu(ref, g);
  in.time_offset_column = timeOffsetRegressor(ref, g, pivot_s);
  const int n = g.count;
  in.tested_temperature_degC.resize(n);
  for (int i = 0; i < n; ++i)
    in.tested_temperature_degC(i) = 20.0 + 12.0 * (1.0 - std::exp(-i * g.bin_s / 150.0));
  in.vibration_f_hp_sq = vibrationLevelPerBin(ref, g, "specific_force_hp_sq");
  in.vibration_w_hp_sq = vibrationLevelPerBin(ref, g, "angular_rate_hp_sq");
  in.C_bn.resize(n);
  double yaw = 0.3, pitch = 0.0, roll = 0.0;
  for (int i = 0; i < n; ++i) {
    yaw += in.reference.omega_rad_s(i, 2) * g.bin_s;
    pitch += in.reference.omega_rad_s(i, 1) * g.bin_s;
    roll += in.reference.omega_rad_s(i, 0) * g.bin_s;
    const Eigen::Matrix3d C_nb = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    in.C_bn[i] = C_nb.transpose();
  }
  const double lat = 0.5, we = 7.292115e-5;
  in.omega_ie_n << we * std::cos(lat), 0.0, -we * std::sin(lat);
  return in;
}

// AR(1) noise per channel: gyro and accel scales typical of a 0.05 s bin of a MEMS IMU.
Eigen::MatrixXd ar1Noise(int n, double rho, uint64_t seed) {
  StandardNormalSampler rng(seed);
  const double scale[6] = {2e-3, 2e-3, 2e-3, 2e-2, 2e-2, 2e-2};
  Eigen::MatrixXd e(n, 6);
  for (int c = 0; c < 6; ++c) {
    double x = rng.next();
    for (int i = 0; i < n; ++i) {
      x = rho * x + std::sqrt(1.0 - rho * rho) * rng.next();
      e(i, c) = scale[c] * x;
    }
  }
  return e;
}

int findTerm(const std::vector<CandidateTerm>& terms, const std::string& key) {
  for (std::size_t t = 0; t < terms.size(); ++t)
    if (terms[t].key() == key) return static_cast<int>(t);
  return -1;
}

struct Injection {
  std::string key;
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
  ASSERT_GE(t, 0) << inj.key;
  const int n = in.reference.size();
  Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(inj.theta.data(), inj.theta.size());
  if (terms[t].fixed) theta = Eigen::VectorXd::Ones(terms[t].columns.size());
  ASSERT_EQ(theta.size(), static_cast<Eigen::Index>(terms[t].columns.size())) << inj.key;
  Eigen::MatrixXd r = termContribution(terms[t], theta, n) + inj.noise_scale * ar1Noise(n, 0.6, 11);
  r.col(0).array() += 1e-3;  // turn-on bias: the nuisance
  r.col(5).array() -= 0.05;

  // The fit holds t and the terms t requires (e.g. the linear term next to a quadratic).
  const SelectionResult fit = fitTerms(r, terms, {t});
  ASSERT_EQ(fit.selected.size(), 1u + terms[t].requires_terms.size()) << inj.key;
  const auto it = std::find_if(fit.selected.begin(), fit.selected.end(),
                               [&](const TermFit& f) { return f.term == t; });
  ASSERT_NE(it, fit.selected.end()) << inj.key;
  const TermFit& tf = *it;
  for (const TermFit& f : fit.selected) {
    if (f.term != t) {
      EXPECT_NE(std::find(terms[t].requires_terms.begin(), terms[t].requires_terms.end(),
                          terms[f.term].key()),
                terms[t].requires_terms.end())
          << terms[f.term].key();
    }
  }
  if (!terms[t].fixed) {
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
    EXPECT_LT(chi2, chiSquareQuantile(0.999, static_cast<double>(e.size()))) << inj.key;
    for (int j : obs) EXPECT_LT(std::abs(err(j)), 3.5 * tf.sigma(j)) << inj.key << " param " << j;
  }
  EXPECT_GT(tf.delta_bic, 10.0) << inj.key;
  EXPECT_GT(tf.cv_gain, 0.0) << inj.key;

  // Selection from the whole library claims this term and at most one other.
  const SelectionResult sel = selectTerms(r, terms);
  bool found = false;
  std::size_t claimed = 0;
  for (const TermFit& s : sel.selected) {
    found |= s.term == t && s.claimed;
    claimed += s.claimed ? 1 : 0;
  }
  EXPECT_TRUE(found) << inj.key;
  EXPECT_LE(claimed, 2u) << inj.key;
}

std::vector<double> G9() { return {2e-4, -1e-4, 3e-4, 1e-4, 2e-4, -2e-4, -3e-4, 1e-4, 2e-4}; }

INSTANTIATE_TEST_SUITE_P(
    AllTerms, MismatchTermRecovery,
    ::testing::Values(
        Injection{"scale_factor:gyro", {3e-3, -2e-3, 1e-2}},
        Injection{"scale_factor:accel", {5e-3, -4e-3, 2e-2}},
        Injection{"non_orthogonality:gyro", {2e-2, -1e-2, 5e-3, 3e-3, -4e-3, 2e-3}},
        Injection{"non_orthogonality:accel", {3e-3, -2e-3, 4e-3, 3e-3, -2e-3, 2e-3}},
        Injection{"g_sensitivity:gyro", G9()},
        Injection{"scale_asymmetry:gyro", {3e-2, -2e-2, 2e-2}},
        Injection{"scale_asymmetry:accel", {2e-2, 1e-2, -1e-2}},
        Injection{"scale_nonlinearity:gyro", {0.5, -0.5, 0.1}},
        Injection{"scale_nonlinearity:accel", {2e-3, -2e-3, 1e-3}},
        Injection{"temperature_bias:gyro", {1e-4, -2e-4, 1e-4}},
        Injection{"temperature_bias:accel", {2e-3, -1e-3, 3e-3}},
        Injection{"temperature_scale:gyro", {1e-3, -1e-3, 5e-4}},
        Injection{"temperature_scale:accel", {5e-4, -5e-4, 5e-4}},
        Injection{"time_offset:both", {0.012}},
        Injection{"lever_arm:accel", {0.4, -0.3, 0.2}},
        Injection{"mounting_misalignment:both", {0.01, -0.01, 0.02}},
        Injection{"vibration_rectification:accel:specific_force_hp_sq", {0.02, -0.03, 0.02}},
        Injection{"vibration_rectification:gyro:specific_force_hp_sq", {2e-3, -2e-3, 3e-3}},
        Injection{"vibration_rectification:gyro:angular_rate_hp_sq", {0.5, 0.3, -0.4}},
        Injection{"earth_rotation_omitted:gyro", {}, 0.01},
        // Tested against a wandering accel bias (requires_terms): needs a quieter (tactical) IMU.
        Injection{"gravity_model:accel", {0.05}, 0.1}),
    [](const ::testing::TestParamInfo<Injection>& info) {
      std::string s = info.param.key;
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
  const int t_nl = findTerm(terms, "scale_nonlinearity:accel");
  const int t_sf = findTerm(terms, "scale_factor:accel");
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
  const int t_rot = findTerm(terms, "mounting_misalignment:both");
  const int t_rem = findTerm(terms, "mounting_rotation_remainder:both");
  ASSERT_GE(t_rot, 0);
  ASSERT_GE(t_rem, 0);
  EXPECT_TRUE(terms[t_rem].fixed);
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
    EXPECT_LT((numeric - analytic).cwiseAbs().maxCoeff(), 1e-7 * numeric.cwiseAbs().maxCoeff() + 1e-9)
        << "column " << j;
  }
  const Eigen::Vector3d dphi(2e-3, -1e-3, 1.5e-3);
  const double err_pivot = (model(phi0 + dphi) - exact(phi0 + dphi)).cwiseAbs().maxCoeff();
  EXPECT_LT(err_pivot, 2.0 * dphi.squaredNorm() * scale / phi0.norm());
  // The first-order columns (pivot 0) miss by about |phi|^2 / 2 of the signal.
  in.mounting_rotation_pivot_rad.setZero();
  const std::vector<CandidateTerm> flat = buildCandidateLibrary(in);
  const int t_flat = findTerm(flat, "mounting_misalignment:both");
  EXPECT_EQ(findTerm(flat, "mounting_rotation_remainder:both"), -1);
  const double err_flat =
      (termContribution(flat[t_flat], phi0 + dphi, n) - exact(phi0 + dphi)).cwiseAbs().maxCoeff();
  EXPECT_GT(err_flat, 50.0 * err_pivot);
}

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
      claimed += terms[sel.selected[0].term].key() + " ";
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
  for (const std::string key : {"scale_factor:gyro", "lever_arm:accel"}) {
    const int t = findTerm(terms, key);
    ASSERT_GE(t, 0) << key;
    const SelectionResult noise_only = selectTerms(ar1Noise(n, 0.3, 500), terms);
    double limit = 0.0;
    for (const TermLimit& l : noise_only.limits)
      if (l.term == t) limit = l.theta_limit(2);
    ASSERT_TRUE(std::isfinite(limit) && limit > 0.0) << key;
    for (const double factor : {2.5, 0.3}) {
      Eigen::VectorXd theta = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(terms[t].columns.size()));
      theta(2) = factor * limit;
      int found = 0;
      for (uint64_t seed = 600; seed < 620; ++seed) {
        const Eigen::MatrixXd r = ar1Noise(n, 0.3, seed) + termContribution(terms[t], theta, n);
        for (const TermFit& tf : selectTerms(r, terms).selected) found += tf.term == t && tf.claimed;
      }
      if (factor > 1.0) {
        EXPECT_GE(found, 18) << key << " at " << factor << " x its limit " << limit;
      } else {
        EXPECT_LE(found, 2) << key << " at " << factor << " x its limit " << limit;
      }
    }
  }
}

}  // namespace
}  // namespace graftnav

namespace graftnav {
namespace {

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
      if (tf.claimed && terms[tf.term].name.rfind("temperature", 0) == 0) {
        ++claimed_temperature;
        log += terms[tf.term].key() + " ";
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

SlowDrive slowDrive(const std::string& term_key) {
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
  const SlowDrive sd = slowDrive("scale_factor:accel");
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
  const std::vector<double> rms =
      rmsErrOverSigma(terms, t, k, 2, {opt, white}, 700, 720, residual);
  EXPECT_GT(rms[0], 0.6);
  EXPECT_LT(rms[0], 1.5);
  EXPECT_GT(rms[1], 2.0 * rms[0]) << "the wander should matter on this motion";
}

// The nuisance constant per channel over n bins, as the library's first term.
CandidateTerm constantNuisance(int n) {
  CandidateTerm t;
  t.name = "constant_bias";
  t.sensor = "both";
  t.nuisance = true;
  for (int c = 0; c < 6; ++c) {
    RegressorColumn col;
    col.channel[c] = Eigen::VectorXd::Ones(n);
    t.columns.push_back(col);
  }
  return t;
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
  terms[1].name = "scale_factor";
  terms[1].sensor = "accel";
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
  const SlowDrive sd = slowDrive("temperature_bias:accel");
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
  const SlowDrive sd = slowDrive("temperature_bias:accel");
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
  const SlowDrive sd = slowDrive("scale_factor:accel");
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
    const SelectionResult with = selectTerms(wander(seed) + termContribution(terms[t], k, n), terms, opt);
    for (const TermFit& tf : with.selected) found += tf.term == t && tf.claimed;
    const SelectionResult null = selectTerms(wander(seed), terms, opt);
    for (const TermFit& tf : null.selected)
      if (tf.claimed) {
        ++null_claims;
        log += terms[tf.term].key() + " ";
      }
  }
  EXPECT_GE(found, 9) << "limit " << limit;
  EXPECT_LE(null_claims, 1) << log;
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
    terms[k].name = "vibration_rectification";
    terms[k].sensor = "gyro";
    terms[k].regressor = k == 1 ? "a" : "b";
    terms[k].excludes = {std::string("vibration_rectification:gyro:") + (k == 1 ? "b" : "a")};
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
  const int g = findTerm(terms, "g_sensitivity:gyro"), tb = findTerm(terms, "temperature_bias:gyro");
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
  const int g = findTerm(terms, "g_sensitivity:gyro");
  const int mis = findTerm(terms, "mounting_misalignment:both");
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
          EXPECT_LT(std::abs(tf.theta(j) - G(j)), 3.5 * tf.sigma(j)) << "seed " << seed << " G " << j;
      } else if (tf.term != mis) {
        ++other;
        log += terms[tf.term].key() + " ";
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
  const int mis = findTerm(terms, "mounting_misalignment:both");
  const int ng = findTerm(terms, "non_orthogonality:gyro");
  const int na = findTerm(terms, "non_orthogonality:accel");
  ASSERT_GE(mis, 0);
  ASSERT_GE(ng, 0);
  ASSERT_GE(na, 0);
  const Eigen::Vector3d phi(0.02, -0.03, 0.05);
  Eigen::VectorXd Ng(6), Na(6);  // off-diagonal elements in row order (01, 02, 10, 12, 20, 21)
  Ng << 4e-3, -3e-3, 1e-3, 5e-3, -2e-3, 3e-3;
  Na << 6e-3, -4e-3, 6e-3, 3e-3, -4e-3, 3e-3;  // symmetric: N_ij = N_ji
  const Eigen::MatrixXd r = termContribution(terms[mis], phi, n) + termContribution(terms[ng], Ng, n) +
                            termContribution(terms[na], Na, n) + ar1Noise(n, 0.5, 31);
  const SelectionResult sel = selectTerms(r, terms);
  const TermFit* rot = nullptr;
  const TermFit* acc = nullptr;
  for (const TermFit& tf : sel.selected) {
    if (tf.term == mis) rot = &tf;
    if (terms[tf.term].name == "non_orthogonality" && terms[tf.term].sensor == "accel") acc = &tf;
  }
  ASSERT_NE(rot, nullptr) << ::testing::PrintToString(sel.log);
  EXPECT_TRUE(rot->claimed);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(rot->theta(a), phi(a), 3.5 * rot->sigma(a)) << "axis " << a;
  ASSERT_NE(acc, nullptr) << ::testing::PrintToString(sel.log);
  EXPECT_EQ(terms[acc->term].regressor, "symmetric");
  const double sym[3] = {Na(0), Na(1), Na(3)};  // pairs 01, 02, 12
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(acc->theta(k), sym[k], 3.5 * acc->sigma(k)) << "pair " << k;
}

}  // namespace
}  // namespace graftnav
