// Mismatch finder, whole pipeline: a synthetic "real" tested IMU made with the composable error
// model (imu_error_model.h) from ideal signals, against a simulation that lacks some of its terms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "graftnav/imu/imu_error_model.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "graftnav/nav/rotation.h"
#include "synthetic_imu.h"

namespace graftnav {
namespace {

// Car-like analytic rates (sinusoids), integrated exactly; a stop at the start.
struct Motion {
  std::array<std::vector<std::array<double, 3>>, 6> waves;  // amp, omega, phase
  Vector6d offset = Vector6d::Zero();
  double rest_s = 20.0;
  // Integral from 0 to t of the rate, with motion ramped in after rest_s (smooth step).
  Vector6d integral(double t) const {
    Vector6d out = offset * t;
    if (t <= rest_s) return out;
    // Integrate numerically the product of the ramp and the waves (Simpson on 1 ms steps is
    // overkill; use the analytic waves times a ramp that is 1 after rest_s + 5 s).
    const double t1 = std::min(t, rest_s + 5.0);
    const int m = 200;
    for (int c = 0; c < 6; ++c) {
      double sum = 0.0;
      for (int k = 0; k < m; ++k) {  // midpoint rule over the ramp interval
        const double u = rest_s + (t1 - rest_s) * (k + 0.5) / m;
        const double ramp = 0.5 - 0.5 * std::cos(M_PI * (u - rest_s) / 5.0);
        for (const auto& w : waves[c]) sum += ramp * w[0] * std::sin(w[1] * u + w[2]);
      }
      out(c) += sum * (t1 - rest_s) / m;
      if (t > rest_s + 5.0)
        for (const auto& w : waves[c])
          out(c) += w[0] / w[1] * (std::cos(w[1] * t1 + w[2]) - std::cos(w[1] * t + w[2]));
    }
    return out;
  }
};

Motion carMotion(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Motion m;
  const double amp[6] = {0.04, 0.04, 0.2, 1.2, 1.5, 0.5};
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k < 6; ++k)
      m.waves[c].push_back({amp[c] * (0.3 + U(rng)), 2.0 * M_PI * (0.01 + 0.5 * U(rng)),
                            2.0 * M_PI * U(rng)});
  m.offset << 0.0, 0.0, 0.0, 0.2, -0.1, -9.79;
  return m;
}

ImuSeries sampleMotion(const Motion& m, double rate_hz, double duration_s) {
  return test::sampleIntegral([&m](double t) { return m.integral(t); }, rate_hz, duration_s, 5000.0);
}

struct Pair {
  DiagnosisInputs in;
  ImuErrorModel truth;
};

// Reference at 100 Hz with a little white noise; "real" tested at 120 Hz with the given model
// plus MEMS-like white noise and a constant bias; simulation = reference + static bias.
Pair makePair(const ImuErrorModel& extra, uint64_t seed) {
  const Motion m = carMotion(seed);
  const double T = 150.0;
  Pair p;
  ImuErrorModel ref_noise;
  ref_noise.gyro.white_noise.density.setConstant(2e-4);
  ref_noise.accel.white_noise.density.setConstant(2e-3);
  p.in.reference = applyErrors(sampleMotion(m, 100.0, T), ref_noise, seed + 1);
  p.truth = extra;
  p.truth.gyro.white_noise.density.setConstant(3e-4);   // 0.017 deg/s/rtHz
  p.truth.accel.white_noise.density.setConstant(3e-3);
  p.truth.gyro.constant_bias.b << 0.01, -0.015, 0.005;
  p.truth.accel.constant_bias.b << 0.1, -0.05, 0.08;
  p.in.real = applyErrors(sampleMotion(m, 120.0, T), p.truth, seed + 2);
  const StaticBiasSimulation sim = simulateFromReferenceAndStaticBias(p.in.reference, p.in.real);
  p.in.simulated = sim.simulated;
  p.in.case_name = "synthetic";
  p.in.simulation_kind = "reference + static bias";
  return p;
}

// White noise only (densities in rad/s/sqrt(Hz) and m/s^2/sqrt(Hz)).
ImuErrorModel whiteNoise(double gyro_density, double accel_density) {
  ImuErrorModel m;
  m.gyro.white_noise.density.setConstant(gyro_density);
  m.accel.white_noise.density.setConstant(accel_density);
  return m;
}

// A simulation that applies `simulated_model` to `reference` (as SG#2 grafts the lab's terms)
// against a real tested IMU with `real_model` on the same motion; noise streams seed, seed + 1.
DiagnosisInputs graftedInputs(const ImuSeries& reference, const ImuErrorModel& real_model,
                              const ImuErrorModel& simulated_model, uint64_t seed,
                              const std::string& simulation_kind) {
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.simulation_kind = simulation_kind;
  in.reference = reference;
  in.real = applyErrors(reference, real_model, seed);
  in.simulated = applyErrors(reference, simulated_model, seed + 1);
  return in;
}

// Whether some note of r contains both a and b.
bool hasNote(const DiagnosisResult& r, const std::string& a, const std::string& b) {
  return std::any_of(r.notes.begin(), r.notes.end(), [&](const std::string& n) {
    return n.find(a) != std::string::npos && n.find(b) != std::string::npos;
  });
}

// The names of r's claimed effects.
std::set<std::string> effectNames(const DiagnosisResult& r) {
  std::set<std::string> names;
  for (const Effect& e : r.effects) names.insert(e.name);
  return names;
}

const Effect* findEffect(const DiagnosisResult& r, const std::string& name) {
  for (const Effect& e : r.effects)
    if (e.name == name) return &e;
  return nullptr;
}

TEST(MismatchDiagnosis, FindsTimeOffsetLeverArmAndGSensitivityOnly) {
  ImuErrorModel extra;
  extra.time_offset.tau_s = 0.018;
  extra.lever_arm.r_m << 0.5, -0.3, 0.2;
  extra.g_sensitivity.G(0, 0) = 4e-4;
  extra.g_sensitivity.G(1, 1) = -3e-4;
  extra.g_sensitivity.G(2, 1) = 3e-4;
  const Pair p = makePair(extra, 3);
  const DiagnosisResult r = diagnose(p.in);
  const std::set<std::string> names = effectNames(r);
  EXPECT_EQ(names, (std::set<std::string>{"time_offset", "lever_arm", "g_sensitivity"}))
      << diagnosisMarkdown(r);
  const Effect* to = findEffect(r, "time_offset");
  ASSERT_NE(to, nullptr);
  EXPECT_NEAR(to->parameters[0].values[0], 0.018, 3.0 * to->parameters[0].sigma[0] + 5e-4);
  const Effect* la = findEffect(r, "lever_arm");
  ASSERT_NE(la, nullptr);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(la->parameters[0].values[a], extra.lever_arm.r_m(a),
                std::max(3.0 * la->parameters[0].sigma[a], 0.2 * std::abs(extra.lever_arm.r_m(a))));
  const Effect* gs = findEffect(r, "g_sensitivity");
  ASSERT_NE(gs, nullptr);
  for (int k = 0; k < 9; ++k)
    EXPECT_NEAR(gs->parameters[0].values[k], extra.g_sensitivity.G(k / 3, k % 3),
                3.5 * gs->parameters[0].sigma[k] + 2e-5) << "G element " << k;
  // The model lowers the residual, also on the held-out second half.
  ASSERT_TRUE(r.has_holdout);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(r.rms_after.accel(a), r.rms_before.accel(a));
    EXPECT_LT(r.holdout_after.accel(a), r.holdout_before.accel(a));
    EXPECT_LT(r.holdout_after.gyro(a), r.holdout_before.gyro(a));
  }
}

// The tested gyros' g-sensitivity reads the specific force at the tested IMU, which a lever
// arm moves by omega_dot x r + omega x (omega x r). Read from the reference's, the difference
// (G times that, even in the yaw rate) is left for other terms: under common random numbers
// random_38_23 claimed a 9-ppm gyro z asymmetry at 8.6 sigma and a 3-us time offset, and G
// came out 15 sigma off. With a lever arm and G selected, G's columns are built from the
// reference moved by the fitted lever arm.
TEST(MismatchDiagnosis, GSensitivityReadsTheSpecificForceAtTheTestedImu) {
  const Motion m = carMotion(21);
  const ImuErrorModel quiet = whiteNoise(3e-6, 3e-5);
  ImuErrorModel real = quiet;
  real.lever_arm.r_m << -0.3, 0.6, -0.2;
  real.g_sensitivity.G << 3e-4, -1e-4, 2e-4, 2e-4, -3e-4, 1e-4, -1e-4, 4e-4, 2e-4;
  const DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, 150.0), real, quiet, 47,
                                           "reference + white noise");
  const DiagnosisResult r = diagnose(in);
  const std::set<std::string> names = effectNames(r);
  EXPECT_EQ(names, (std::set<std::string>{"lever_arm", "g_sensitivity"})) << diagnosisMarkdown(r);
  const Effect* gs = findEffect(r, "g_sensitivity");
  ASSERT_NE(gs, nullptr);
  for (int k = 0; k < 9; ++k)
    EXPECT_NEAR(gs->parameters[0].values[k], real.g_sensitivity.G(k / 3, k % 3),
                3.0 * gs->parameters[0].sigma[k]) << "G element " << k;
}

// Separately started loggers: offsets of seconds are found by the coarse stage and refined.
TEST(MismatchTimeOffset, CoarseStageFindsOffsetsOfSeconds) {
  const Motion m = carMotion(4);
  const ImuSeries ref = sampleMotion(m, 100.0, 150.0);
  for (double tau : {2.37, -3.104, 0.0213}) {
    const ImuSeries tested = test::sampleIntegral(
        [&m, tau](double t) { return m.integral(t - tau); }, 120.0, 150.0, 5000.0);
    const TimeOffsetEstimate est = estimateTimeOffset(ref, tested);
    EXPECT_TRUE(est.reliable) << "tau " << tau;
    EXPECT_NEAR(est.tau_s, tau, 1.5e-3) << "tau " << tau;
    TimeOffsetOptions fine_only;
    fine_only.coarse_max_offset_s = 0.0;
    if (std::abs(tau) > 1.0) {  // the fine search alone cannot reach it
      EXPECT_GT(std::abs(estimateTimeOffset(ref, tested, fine_only).tau_s - tau), 0.5);
    }
  }
}

// A 1.3-s offset is taken out of the real record's tags before binning; the time_offset reported
// is the whole offset, and the lever arm comes back as with a small offset.
TEST(MismatchDiagnosis, LargeTimeOffsetIsRealignedAndReported) {
  ImuErrorModel extra;
  extra.time_offset.tau_s = 1.3;
  extra.lever_arm.r_m << 0.5, -0.3, 0.2;
  const Pair p = makePair(extra, 3);
  const DiagnosisResult r = diagnose(p.in);
  const Effect* to = findEffect(r, "time_offset");
  ASSERT_NE(to, nullptr) << diagnosisMarkdown(r);
  EXPECT_NEAR(to->parameters[0].values[0], 1.3, 3.0 * to->parameters[0].sigma[0] + 1e-3);
  const Effect* la = findEffect(r, "lever_arm");
  ASSERT_NE(la, nullptr) << diagnosisMarkdown(r);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(la->parameters[0].values[a], extra.lever_arm.r_m(a),
                std::max(3.0 * la->parameters[0].sigma[a], 0.2 * std::abs(extra.lever_arm.r_m(a))));
  for (int a = 0; a < 3; ++a) EXPECT_LT(r.rms_after.gyro(a), 0.1 * r.rms_raw.gyro(a));
}

// Lost samples: 1.5 s of the real record missing, the sample after the gap stretched over it (as
// the reader does: dt = t_k - t_{k-1}), so it carries 8 ms of increments for 1.5 s. The bins
// overlapping the gap are left out and listed; the same effects are found as without the gap
// (before: its bins' residual, of the size of the motion itself, bent every fit).
TEST(MismatchDiagnosis, BinsOverlappingASamplingGapAreLeftOut) {
  ImuErrorModel extra;
  extra.time_offset.tau_s = 0.018;
  extra.lever_arm.r_m << 0.5, -0.3, 0.2;
  Pair p = makePair(extra, 3);
  ImuSeries gapped;
  for (const ImuSample& s : p.in.real) {
    if (s.t_s > 5060.0 && s.t_s <= 5061.5) continue;
    gapped.push_back(s);
    if (gapped.size() > 1) gapped.back().dt_s = gapped.back().t_s - gapped[gapped.size() - 2].t_s;
  }
  ASSERT_LT(gapped.size(), p.in.real.size() - 150);
  p.in.real = gapped;
  const DiagnosisResult r = diagnose(p.in);
  ASSERT_EQ(r.masked_spans.size(), 1u) << diagnosisMarkdown(r);
  EXPECT_LE(r.masked_spans[0].first, 5060.0);
  EXPECT_GE(r.masked_spans[0].second, 5061.5);
  EXPECT_LT(r.masked_spans[0].second - r.masked_spans[0].first, 1.8);
  const std::set<std::string> names = effectNames(r);
  EXPECT_EQ(names, (std::set<std::string>{"time_offset", "lever_arm"})) << diagnosisMarkdown(r);
  const Effect* la = findEffect(r, "lever_arm");
  ASSERT_NE(la, nullptr);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(la->parameters[0].values[a], extra.lever_arm.r_m(a),
                std::max(3.0 * la->parameters[0].sigma[a], 0.2 * std::abs(extra.lever_arm.r_m(a))));
  for (int a = 0; a < 3; ++a) EXPECT_LT(r.rms_after.accel(a), 0.05) << "gap bins left in the RMS";
}

// A gyro z scale asymmetry that the simulation partly holds as a quadratic (what SG#2's lab
// fitting polynomial makes of an asymmetry seen on a rate table): the reported k_pos - k_neg is
// the sensor's own, not only the part the simulation lacks (before: 17 % low, 5.5 sigma, on the
// concealed scale_asymmetry case), and the quadratic is not claimed as the sensor's.
TEST(MismatchDiagnosis, ScaleAsymmetryReportsTheSensorsOwnGainsPerSign) {
  ImuErrorModel extra;
  extra.gyro.scale_asymmetry.k_pos << 0.0, 0.0, 0.02;
  extra.gyro.scale_asymmetry.k_neg << 0.0, 0.0, -0.02;
  Pair p = makePair(extra, 5);
  const double c2 = 0.003;  // simulation: + c2 omega_z^2 (rad/s per (rad/s)^2)
  for (ImuSample& smp : p.in.simulated) {
    const double w = smp.dtheta_rad.z() / smp.dt_s;
    smp.dtheta_rad.z() += c2 * w * w * smp.dt_s;
  }
  // The lab polynomial that put c2 there is known (as diagnose passes it): the residual's
  // quadratic only cancels it and must not be claimed as the sensor's non-linearity.
  LabQuadratic lab;
  lab.c2 << 0.0, 0.0, c2;
  lab.c2_sigma << 0.0, 0.0, c2 / 50.0;
  p.in.priors[Sensor::gyro].lab_quadratic = lab;
  const DiagnosisResult r = diagnose(p.in);
  const Effect* sa = findEffect(r, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(r);
  ASSERT_GE(sa->parameters.size(), 4u);
  EXPECT_EQ(sa->parameters[0].key, "k_pos");
  EXPECT_EQ(sa->parameters[1].key, "k_neg");
  EXPECT_EQ(sa->parameters[2].key, "k_pos_missing");
  const double d = sa->parameters[0].values[2] - sa->parameters[1].values[2];
  const double sd = std::hypot(sa->parameters[0].sigma[2], sa->parameters[1].sigma[2]);
  EXPECT_NEAR(d, 0.04, 3.0 * sd) << diagnosisMarkdown(r);
  EXPECT_EQ(findEffect(r, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(r);
}

// The gains per sign are reported relative to the simulation's linear gain: a tested gyro with a
// 0.2-0.3 % scale factor that the lab calibrated (SG#2 holds it) and a symmetric asymmetry +-d
// on z comes back as k_pos = +d, k_neg = -d element by element, not as the sensor's whole gains
// (scale factor +- d; before the fifteenth session k_pos z was 0.007 here, 20 sigma off).
TEST(MismatchDiagnosis, ScaleAsymmetryGainsAreRelativeToTheSimulationsGain) {
  const Motion m = carMotion(11);
  const ImuErrorModel noise = whiteNoise(3e-4, 3e-3);
  ImuErrorModel sg2 = noise;
  sg2.gyro.scale_factor.k << -2e-3, 2.5e-3, 3e-3;  // the lab's calibrated gain error
  ImuErrorModel real = sg2;
  const double d = 0.004;
  real.gyro.scale_asymmetry.k_pos << 0.0, 0.0, d;
  real.gyro.scale_asymmetry.k_neg << 0.0, 0.0, -d;
  const DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, 150.0), real, sg2, 41,
                                           "reference + the lab's scale factor (as SG#2)");
  const DiagnosisResult r = diagnose(in);
  const Effect* sa = findEffect(r, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(r);
  ASSERT_GE(sa->parameters.size(), 2u);
  const EffectParameter& kp = sa->parameters[0];
  const EffectParameter& kn = sa->parameters[1];
  ASSERT_EQ(kp.key, "k_pos");
  ASSERT_EQ(kn.key, "k_neg");
  for (int a = 0; a < 3; ++a) {
    const double truth_pos = real.gyro.scale_asymmetry.k_pos(a);
    const double truth_neg = real.gyro.scale_asymmetry.k_neg(a);
    EXPECT_NEAR(kp.values[a], truth_pos, 3.0 * kp.sigma[a]) << "axis " << a << "\n"
                                                             << diagnosisMarkdown(r);
    EXPECT_NEAR(kn.values[a], truth_neg, 3.0 * kn.sigma[a]) << "axis " << a;
  }
  EXPECT_LT(kp.sigma[2], 0.1 * d) << "z is determined";

  // The lab's z gain 1e-3 off, twice the uncertainty it states: the residual's scale factor
  // (gated as calibration error, not claimed) holds it, and so do the gains per sign measured
  // about the simulation's gain. Their uncertainty includes the lab's: against the sensor's own
  // gains +-d they stay within 3 sigma (with the fits' sigma alone k_pos was 4.2 sigma off).
  ImuErrorModel real_off = real;
  real_off.gyro.scale_factor.k(2) += 1e-3;
  DiagnosisInputs off = graftedInputs(sampleMotion(m, 100.0, 150.0), real_off, sg2, 43,
                                      "reference + the lab's scale factor (as SG#2)");
  off.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(5e-4);
  off.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  const DiagnosisResult r_off = diagnose(off);
  EXPECT_EQ(findEffect(r_off, "scale_factor"), nullptr) << diagnosisMarkdown(r_off);
  const Effect* sa_off = findEffect(r_off, "scale_asymmetry");
  ASSERT_NE(sa_off, nullptr) << diagnosisMarkdown(r_off);
  EXPECT_GT(sa_off->parameters[0].values[2] + sa_off->parameters[1].values[2], 1e-3)
      << "the mean of the gains per sign holds the lab's error (2 x 1e-3 expected)";
  EXPECT_NEAR(sa_off->parameters[0].values[2], d, 3.0 * sa_off->parameters[0].sigma[2])
      << diagnosisMarkdown(r_off);
  EXPECT_NEAR(sa_off->parameters[1].values[2], -d, 3.0 * sa_off->parameters[1].sigma[2]);
}

// The asymmetry gate weighs the half-difference d of the gains per sign against what the lab
// can put there: not its gain (an error of it moves both gains alike; until the eighteenth
// session 2 M_sigma^2 sat in the gate and held back random_36_23's gyro asymmetry at 1.6 x its
// limit), but the error of a quadratic it kept, which is even in x like |x|.
TEST(MismatchDiagnosis, AsymmetryGateWeighsTheLabQuadraticNotItsGain) {
  const Motion m = carMotion(11);
  const ImuErrorModel noise = whiteNoise(3e-4, 3e-3);
  ImuErrorModel real = noise;
  const double d = 0.004;
  real.gyro.scale_asymmetry.k_pos << 0.0, 0.0, d;
  real.gyro.scale_asymmetry.k_neg << 0.0, 0.0, -d;
  DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, 150.0), real, noise, 45,
                                     "reference + the lab's noise (as SG#2)");
  // A lab gain as uncertain as the asymmetry: it cancels in k_pos - k_neg.
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(d);
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  const DiagnosisResult loose_gain = diagnose(in);
  const Effect* sa = findEffect(loose_gain, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(loose_gain);
  EXPECT_NEAR(sa->parameters[0].values[2] - sa->parameters[1].values[2], 2.0 * d,
              3.0 * std::hypot(sa->parameters[0].sigma[2], sa->parameters[1].sigma[2]));

  // The lab kept a z quadratic (zero) to +-0.1 per rad/s: on this drive's yaw rates its error
  // reads on |x| as 0.37 rad/s x 0.1 = 0.037, nine times d. Not claimed, and said why.
  LabQuadratic lab;
  lab.c2_sigma << 0.0, 0.0, 0.1;
  in.priors[Sensor::gyro].lab_quadratic = lab;
  const DiagnosisResult loose_c2 = diagnose(in);
  EXPECT_EQ(findEffect(loose_c2, "scale_asymmetry"), nullptr) << diagnosisMarkdown(loose_c2);
  EXPECT_TRUE(hasNote(loose_c2, "gyro scale_asymmetry fitted but within 3 sigma", "lab quadratic"))
      << diagnosisMarkdown(loose_c2);
}

// The lab's poses at +-g see an accelerometer's asymmetric gain d |x| as a quadratic c2 x^2 with
// c2 = d / g, which SG#2 grafts. Measured with plain |x| columns the asymmetry needs a quadratic
// column beside it to cancel SG#2's (and on the field's small inputs |x| and x^2 are nearly
// collinear: under common random numbers random_13_26 and 14_10 came out 41 and 39 % off). The
// alternative term takes SG#2's known quadratic out instead, so the asymmetry is measured as
// precisely as on a sensor whose lab saw no curvature (3 x less precisely without it here).
TEST(MismatchDiagnosis, AccelAsymmetryReplacesTheLabQuadraticItWasSeenAs) {
  const Motion m = carMotion(37);
  const double T = 150.0, g = 9.79;
  const Eigen::Vector3d k_pos(6e-3, -5e-3, 0.0);
  const ImuErrorModel noise = whiteNoise(3e-5, 1e-5);
  ImuErrorModel truth = noise;
  truth.accel.scale_asymmetry.k_pos = k_pos;
  truth.accel.scale_asymmetry.k_neg.setZero();
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.reference = sampleMotion(m, 100.0, T);
  in.real = applyErrors(in.reference, truth, 71);
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  // SG#2 with the lab's line (the mean gain), and with or without the quadratic of the poses.
  const auto run = [&](bool lab_quadratic) {
    ImuErrorModel sg2 = noise;
    sg2.accel.scale_factor.k = 0.5 * k_pos;
    in.priors[Sensor::accel].lab_quadratic.reset();
    if (lab_quadratic) {
      LabQuadratic lab;
      lab.c2 = 0.5 * k_pos / g;
      lab.c2_sigma = Eigen::Vector3d(1e-5, 1e-5, 0.0);
      sg2.accel.scale_nonlinearity.k2 = lab.c2;
      in.priors[Sensor::accel].lab_quadratic = lab;
    }
    in.simulation_kind = lab_quadratic ? "reference + the lab's line and quadratic (as SG#2)"
                                       : "reference + the lab's line (as SG#2)";
    in.simulated = applyErrors(in.reference, sg2, 72);
    return diagnose(in);
  };
  const DiagnosisResult plain = run(false), folded = run(true);
  EXPECT_EQ(findEffect(folded, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(folded);
  const Effect* sa = findEffect(folded, "scale_asymmetry");
  const Effect* sa_plain = findEffect(plain, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(folded);
  ASSERT_NE(sa_plain, nullptr) << diagnosisMarkdown(plain);
  ASSERT_GE(sa->parameters.size(), 4u);
  for (int a = 0; a < 2; ++a) {
    const double d = sa->parameters[0].values[a] - sa->parameters[1].values[a];
    const double sd = std::hypot(sa->parameters[0].sigma[a], sa->parameters[1].sigma[a]);
    EXPECT_NEAR(d, k_pos(a), 3.0 * sd) << "axis " << a << "\n" << diagnosisMarkdown(folded);
    // The fit's precision (k_pos_missing: the residual fit's sigma; k_pos adds the lab's gain
    // uncertainty, and with the quadratic its c2 sigma at the mean input).
    EXPECT_LT(sa->parameters[2].sigma[a], 1.3 * sa_plain->parameters[2].sigma[a])
        << "axis " << a << "\n" << diagnosisMarkdown(folded);
  }
  // SG#3 takes the lab's quadratic out: it is no longer listed as in the simulation.
  for (const Effect& e : folded.in_simulation) EXPECT_NE(e.sensor, "accel");
}

// The gains per sign are measured on tested minus reference, which holds the sensor's own
// curvature too. Where the lab kept a quadratic, that curvature is its c2 less the asymmetry's fold
// (c2 = k2 + d / g on six-position poses); fitted with |x| alone, a curvature the lab measured
// leaked into d (random_31_23: d_x 16 % high; here, with MEMS noise, d came out 2.2 times the
// injected, 25 sigma off). An accelerometer x asymmetry beside a true x curvature.
TEST(MismatchDiagnosis, GainsPerSignAreMeasuredBesideTheCurvatureTheLabMeasured) {
  const Motion m = carMotion(37);
  const double T = 150.0, g = 9.79, d = 3e-3, k2 = 1e-3;
  const ImuErrorModel noise = whiteNoise(3e-5, 1e-3);
  ImuErrorModel truth = noise;
  truth.accel.scale_asymmetry.k_pos << 2.0 * d, 0.0, 0.0;  // one-sided: +-d about the mean
  truth.accel.scale_asymmetry.k_neg.setZero();
  truth.accel.scale_nonlinearity.k2 << k2, 0.0, 0.0;
  ImuErrorModel sg2 = noise;
  sg2.accel.scale_factor.k << d, 0.0, 0.0;  // the lab's line: the mean gain
  LabQuadratic lab;
  lab.c2 << k2 + d / g, 0.0, 0.0;  // what its poses measured
  lab.c2_sigma << 1e-6, 0.0, 0.0;
  lab.c2_tested = lab.c2;
  lab.c2_tested_sigma = Eigen::Vector3d::Constant(1e-6);
  lab.slope_per_abs.setZero();
  lab.slope_per_sq.setZero();
  lab.c2_tested_per_abs.setConstant(1.0 / g);
  sg2.accel.scale_nonlinearity.k2 = lab.c2;
  DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, T), truth, sg2, 81,
                                     "reference + the lab's line and quadratic (as SG#2)");
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  in.priors[Sensor::accel].lab_quadratic = lab;
  const DiagnosisResult r = diagnose(in);
  const Effect* sa = findEffect(r, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(r);
  EXPECT_NEAR(sa->parameters[0].values[0], d, 3.0 * sa->parameters[0].sigma[0])
      << diagnosisMarkdown(r);
  EXPECT_NEAR(sa->parameters[1].values[0], -d, 3.0 * sa->parameters[1].sigma[0]);
  EXPECT_LT(sa->parameters[0].sigma[0], 0.1 * d) << "x is determined";
  // The field does not claim the curvature here (MEMS noise): the lab's is what holds it.
  EXPECT_EQ(findEffect(r, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(r);
}

// An accelerometer z curvature that the lab's degree test dropped (as on random_26_05) is, in
// the field, a z gain at f_z ~ -g. The lab's degree-2 estimate names it: a curvature when it
// agrees, a gain change when the lab saw none, not settled when the lab is too coarse to tell.
TEST(MismatchDiagnosis, OneSignedGainIsNamedByTheLabsCurvatureEstimate) {
  const ImuSeries reference = sampleMotion(carMotion(23), 100.0, 150.0);
  // MEMS-like accelerometer noise: the field sees the slope at -g (k delta_f_z), not the
  // curvature's own k2 delta_f_z^2 (with 10 x less noise it does, and names x^2 itself).
  const ImuErrorModel noise = whiteNoise(3e-5, 1e-3);
  const double k2 = -1e-4, g = 9.79;
  const auto run = [&](bool curvature, double c2_tested, double c2_tested_sigma) {
    ImuErrorModel real = noise;
    if (curvature)
      real.accel.scale_nonlinearity.k2 << 0.0, 0.0, k2;
    else
      real.accel.scale_factor.k << 0.0, 0.0, -2.0 * g * k2;  // the same slope at -g
    DiagnosisInputs in = graftedInputs(reference, real, noise, 51,
                                       "reference + the lab's line (as SG#2)");
    in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
    in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
    LabQuadratic lab;  // lines on all axes; the degree-2 estimates the test dropped
    lab.c2_tested << 0.0, 0.0, c2_tested;
    lab.c2_tested_sigma << 2e-5, 2e-5, c2_tested_sigma;
    in.priors[Sensor::accel].lab_quadratic = lab;
    return diagnose(in);
  };
  const DiagnosisResult bent = run(true, 0.9 * k2, 2e-5);
  const Effect* nl = findEffect(bent, "scale_nonlinearity");
  ASSERT_NE(nl, nullptr) << diagnosisMarkdown(bent);
  EXPECT_EQ(nl->sensor, "accel");
  EXPECT_EQ(findEffect(bent, "scale_factor"), nullptr) << diagnosisMarkdown(bent);
  EXPECT_NEAR(nl->parameters[0].values[2], k2, 3.0 * nl->parameters[0].sigma[2])
      << diagnosisMarkdown(bent);
  EXPECT_LT(nl->parameters[0].sigma[2], 0.2 * std::abs(k2));

  const DiagnosisResult gain = run(false, 1e-6, 2e-5);
  const Effect* sf = findEffect(gain, "scale_factor");
  ASSERT_NE(sf, nullptr) << diagnosisMarkdown(gain);
  EXPECT_NEAR(sf->parameters[0].values[2], -2.0 * g * k2, 3.0 * sf->parameters[0].sigma[2]);
  EXPECT_EQ(findEffect(gain, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(gain);

  const DiagnosisResult coarse = run(true, 0.9 * k2, 3e-4);
  EXPECT_EQ(findEffect(coarse, "scale_factor"), nullptr) << diagnosisMarkdown(coarse);
  EXPECT_EQ(findEffect(coarse, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(coarse);
  ASSERT_EQ(coarse.ambiguous.size(), 1u) << diagnosisMarkdown(coarse);
  EXPECT_EQ(coarse.ambiguous[0].alternative, "scale_nonlinearity");
}

// A one-sided accelerometer z asymmetry the lab folded into the quadratic it kept (as on
// random_23_13): SG#2 grafts the mean gain and c2 = d / g, and at f_z ~ -g the field's slope is
// off by d, which was claimed as a z scale factor. Weighed with the lab's quadratic and its
// responses (six-position poses: slope_per_abs 0, c2_tested_per_abs 1 / g), the asymmetry
// explains both and is named; a real z curvature in the lab's quadratic with a gain change
// between lab and field is not settled (a gain beside the curvature and an asymmetry beside a
// curvature fit alike) and is not claimed.
TEST(MismatchDiagnosis, OneSignedGainIsWeighedAgainstAnAsymmetryTheLabFolded) {
  const ImuSeries reference = sampleMotion(carMotion(23), 100.0, 150.0);
  const ImuErrorModel noise = whiteNoise(3e-5, 1e-3);
  const double g = 9.79, k2_x = 1e-3;
  const auto run = [&](bool asymmetry) {
    ImuErrorModel real = noise, sg2 = noise;
    real.accel.scale_nonlinearity.k2 << k2_x, 0.0, 0.0;
    LabQuadratic lab;
    lab.c2 << k2_x, 0.0, 0.0;
    if (asymmetry) {
      const double a = -6e-3;  // gain 1 + a on the positive side, 1 on the negative
      real.accel.scale_asymmetry.k_pos << 0.0, 0.0, a;
      real.accel.scale_asymmetry.k_neg.setZero();
      sg2.accel.scale_factor.k << 0.0, 0.0, 0.5 * a;  // the lab's line: the mean gain
      lab.c2(2) = 0.5 * a / g;                         // and its quadratic: d / g
    } else {
      real.accel.scale_nonlinearity.k2(2) = -2e-4;  // a real z curvature the lab measured
      real.accel.scale_factor.k << 0.0, 0.0, 3e-3;  // and a gain change since
      lab.c2(2) = -2e-4;
    }
    sg2.accel.scale_nonlinearity.k2 = lab.c2;
    lab.c2_sigma << 1e-5, 0.0, 1e-5;
    lab.c2_tested = lab.c2;
    lab.c2_tested_sigma = Eigen::Vector3d::Constant(1e-5);
    lab.slope_per_abs.setZero();
    lab.slope_per_sq.setZero();
    lab.c2_tested_per_abs.setConstant(1.0 / g);
    DiagnosisInputs in = graftedInputs(reference, real, sg2, 53,
                                       "reference + the lab's line and quadratic (as SG#2)");
    in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
    in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
    in.priors[Sensor::accel].lab_quadratic = lab;
    return diagnose(in);
  };
  const DiagnosisResult folded = run(true);
  EXPECT_EQ(findEffect(folded, "scale_factor"), nullptr) << diagnosisMarkdown(folded);
  const Effect* sa = findEffect(folded, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(folded);
  EXPECT_EQ(sa->sensor, "accel");
  // Gains per sign about the lab's mean gain: +-d on z, d = a / 2.
  EXPECT_NEAR(sa->parameters[0].values[2], -3e-3, 3.0 * sa->parameters[0].sigma[2])
      << diagnosisMarkdown(folded);
  EXPECT_NEAR(sa->parameters[1].values[2], 3e-3, 3.0 * sa->parameters[1].sigma[2]);
  EXPECT_LT(sa->parameters[0].sigma[2], 0.3 * 3e-3);

  const DiagnosisResult gain = run(false);
  EXPECT_EQ(findEffect(gain, "scale_factor"), nullptr) << diagnosisMarkdown(gain);
  EXPECT_EQ(findEffect(gain, "scale_asymmetry"), nullptr) << diagnosisMarkdown(gain);
  ASSERT_EQ(gain.ambiguous.size(), 1u) << diagnosisMarkdown(gain);
  EXPECT_EQ(gain.ambiguous[0].effect.name, "scale_factor");
  EXPECT_EQ(gain.ambiguous[0].alternative, "scale_asymmetry");
  EXPECT_NEAR(gain.ambiguous[0].effect.parameters[0].values[2], 3e-3,
              3.0 * gain.ambiguous[0].effect.parameters[0].sigma[2]);
}

// |x| (scale_asymmetry) and x^2 (scale_nonlinearity) are two shapes of one even response; on
// this motion the gyro z x^2 column holds nearly all of its term's trace, so the term-isotropic
// prior charged x^2 about 8 less than |x| and an asymmetry near its limit was claimed as a
// non-linearity (as on random_23_23). A name needs min_name_margin of evidence over the other
// shape, measured with each column under its own prior: near the limit the margin leans to the
// true shape (with the term prior it leaned to x^2: +2.8 for x^2 on seed 5).
TEST(MismatchDiagnosis, EvenShapeIsNamedOnlyWithEvidenceOverTheOther) {
  const auto run = [](double d, double k2, int seed) {
    ImuErrorModel extra;
    extra.gyro.scale_asymmetry.k_pos << 0.0, 0.0, d;
    extra.gyro.scale_asymmetry.k_neg << 0.0, 0.0, -d;
    extra.gyro.scale_nonlinearity.k2 << 0.0, 0.0, k2;
    return diagnose(makePair(extra, seed).in);
  };
  // Near the limit: found and modelled, never named x^2; named |x| or left ambiguous with the
  // margin on the side of |x|.
  int ambiguous = 0;
  for (int seed : {5, 6, 7}) {
    const DiagnosisResult near = run(0.0015, 0.0, seed);
    EXPECT_EQ(findEffect(near, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(near);
    EXPECT_LT(near.rms_after.gyro(2), 0.99 * near.rms_before.gyro(2)) << "modelled in SG#3";
    if (findEffect(near, "scale_asymmetry") != nullptr) continue;
    ASSERT_EQ(near.ambiguous.size(), 1u) << diagnosisMarkdown(near);
    const AmbiguousEffect& a = near.ambiguous[0];
    ++ambiguous;
    EXPECT_EQ(a.effect.sensor, "gyro");
    EXPECT_LT(a.name_margin, SelectionOptions{}.min_name_margin);
    const double for_abs = a.effect.name == "scale_asymmetry" ? a.name_margin : -a.name_margin;
    EXPECT_GT(for_abs, 0.0) << "seed " << seed << "\n" << diagnosisMarkdown(near);
    const nlohmann::json j = nlohmann::json::parse(diagnosisJson(near));
    ASSERT_EQ(j["ambiguous"].size(), 1u);
    EXPECT_EQ(j["ambiguous"][0]["alternative"], a.alternative);
    EXPECT_TRUE(j["ambiguous"][0]["evidence"].contains("name_margin"));
  }
  EXPECT_GE(ambiguous, 1) << "0.0015 is meant to sit where the shape is not settled";
  // Each shape named when it fits clearly better.
  const DiagnosisResult asym = run(0.002, 0.0, 5), quad = run(0.0, 0.005, 5);
  EXPECT_NE(findEffect(asym, "scale_asymmetry"), nullptr) << diagnosisMarkdown(asym);
  EXPECT_EQ(findEffect(asym, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(asym);
  EXPECT_TRUE(asym.ambiguous.empty()) << diagnosisMarkdown(asym);
  EXPECT_NE(findEffect(quad, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(quad);
  EXPECT_EQ(findEffect(quad, "scale_asymmetry"), nullptr) << diagnosisMarkdown(quad);
  EXPECT_TRUE(quad.ambiguous.empty()) << diagnosisMarkdown(quad);
}

TEST(MismatchDiagnosis, NullPairClaimsNothing) {
  const Pair p = makePair(ImuErrorModel{}, 9);
  const DiagnosisResult r = diagnose(p.in);
  EXPECT_TRUE(r.effects.empty()) << diagnosisMarkdown(r);
}

TEST(MismatchDiagnosis, ExpectedWanderOfTwoRealizations) {
  LabNoiseFigures lab;
  lab.bias_instability << 1e-3, 0.0, 2e-3;
  lab.rate_random_walk << 0.0, 3e-4, 1e-4;
  const Eigen::Vector3d sd = expectedWanderSd(lab, 1200.0);
  EXPECT_NEAR(sd(0), std::sqrt(2.0) * 1e-3, 1e-12);                      // B only
  EXPECT_NEAR(sd(1), 3e-4 * std::sqrt(400.0), 1e-12);                    // K sqrt(T / 3)
  EXPECT_NEAR(sd(2), std::sqrt(2.0 * 4e-6 + 1e-8 * 400.0), 1e-12);       // both
}

// A tested accelerometer whose bias random-walks (1.5e-3 m/s^2/sqrt(s): ~0.008 m/s^2 over the
// record, well above the per-window noise) against a simulation that holds a constant bias. With
// the lab's figures saying so, that wander is noise: no accel span is unexplained. With figures
// 30 times smaller it is beyond them and is reported (as a claimed bias_instability, or as
// unexplained spans).
TEST(MismatchDiagnosis, WanderWithinTheLabNoiseFiguresIsNotUnexplained) {
  ImuErrorModel extra;
  extra.accel.bias_random_walk.density.setConstant(1.5e-3);
  Pair p = makePair(extra, 21);
  auto accelSpans = [](const DiagnosisResult& r) {
    int k = 0;
    for (const LocatedSpan& s : r.unexplained) k += s.channel.rfind("accel", 0) == 0;
    return k;
  };
  const DiagnosisResult without = diagnose(p.in);
  ASSERT_GT(accelSpans(without), 0) << "the wander must be visible without lab figures\n"
                                    << diagnosisMarkdown(without);
  EXPECT_TRUE(without.wander.empty());

  LabNoiseFigures lab;
  lab.rate_random_walk.setConstant(1.5e-3);
  p.in.priors[Sensor::accel].lab_noise = lab;
  const DiagnosisResult within = diagnose(p.in);
  ASSERT_EQ(within.wander.size(), 3u);  // accel channels only: no gyro figures given
  for (const WanderCheck& k : within.wander) {
    EXPECT_TRUE(k.within) << k.channel << " sd " << k.fitted_sd << " limit " << k.limit;
    EXPECT_GT(k.fitted_sd, 0.2 * k.expected_sd) << k.channel;  // the fit sees the wander
  }
  EXPECT_EQ(accelSpans(within), 0) << diagnosisMarkdown(within);

  lab.rate_random_walk.setConstant(5e-5);
  p.in.priors[Sensor::accel].lab_noise = lab;
  const DiagnosisResult beyond = diagnose(p.in);
  int outside = 0;
  for (const WanderCheck& k : beyond.wander) outside += !k.within;
  EXPECT_GT(outside, 0) << diagnosisMarkdown(beyond);
  const Effect* bi = findEffect(beyond, "bias_instability");
  EXPECT_TRUE(accelSpans(beyond) > 0 || (bi && bi->sensor == "accel")) << diagnosisMarkdown(beyond);
}

// SG#2 grafts the lab polynomial's quadratic c2; when the real sensor has none (e.g. a scale
// asymmetry folded into c2 on the rate table), the residual shows -c2 x^2. That is the
// simulation's artefact: modelled, not claimed as a non-linearity of the sensor. A sensor with a
// quadratic of its own (here 2 c2, the lab seeing half of it) is claimed with its own k2.
TEST(MismatchDiagnosis, ScaleNonlinearityReportsTheSensorsOwnQuadratic) {
  const double c2 = 0.01;  // per rad/s, gyro z
  ImuErrorModel spurious;
  spurious.gyro.scale_nonlinearity.k2 << 0.0, 0.0, c2;
  LabQuadratic lab;
  lab.c2 << 0.0, 0.0, c2;
  lab.c2_sigma << 0.0, 0.0, c2 / 50.0;
  auto k2Of = [](const DiagnosisResult& r, const std::string& key) -> const EffectParameter* {
    const Effect* e = findEffect(r, "scale_nonlinearity");
    if (!e || e->sensor != "gyro") return nullptr;
    for (const EffectParameter& q : e->parameters)
      if (q.key == key) return &q;
    return nullptr;
  };

  Pair p = makePair(ImuErrorModel{}, 31);
  p.in.simulated = applyErrors(p.in.simulated, spurious, 0);
  const DiagnosisResult plain = diagnose(p.in);  // without the lab's polynomial
  const EffectParameter* k = k2Of(plain, "k2");
  ASSERT_NE(k, nullptr) << diagnosisMarkdown(plain);
  EXPECT_NEAR(k->values[2], -c2, 3.0 * k->sigma[2]);

  p.in.priors[Sensor::gyro].lab_quadratic = lab;
  const DiagnosisResult artefact = diagnose(p.in);
  EXPECT_EQ(k2Of(artefact, "k2"), nullptr) << diagnosisMarkdown(artefact);
  // The residual cancels the lab's c2: not the sensor's, so not listed as in the simulation.
  EXPECT_TRUE(plain.in_simulation.empty());
  EXPECT_TRUE(artefact.in_simulation.empty()) << diagnosisMarkdown(artefact);
  // 0.92 on this seed: the quadratic is ~40 % of the per-bin noise.
  EXPECT_LT(artefact.rms_after.gyro(2), 0.96 * artefact.rms_before.gyro(2))
      << "the artefact stays in the model (SG#3)\n" << diagnosisMarkdown(artefact);

  ImuErrorModel own;
  own.gyro.scale_nonlinearity.k2 << 0.0, 0.0, 2.0 * c2;
  Pair q = makePair(own, 31);
  q.in.simulated = applyErrors(q.in.simulated, spurious, 0);
  q.in.priors[Sensor::gyro].lab_quadratic = lab;
  const DiagnosisResult real_nl = diagnose(q.in);
  const EffectParameter* k_own = k2Of(real_nl, "k2");
  const EffectParameter* k_missing = k2Of(real_nl, "k2_missing");
  ASSERT_NE(k_own, nullptr) << diagnosisMarkdown(real_nl);
  ASSERT_NE(k_missing, nullptr);
  EXPECT_NEAR(k_own->values[2], 2.0 * c2, 3.0 * k_own->sigma[2]);
  EXPECT_NEAR(k_missing->values[2], c2, 3.0 * k_missing->sigma[2]);
  EXPECT_TRUE(real_nl.in_simulation.empty());  // the claimed k2 includes the lab's c2

  // The same sensor, but the lab states c2 to +-c2 / 2: the missing part (2 lab sigma) is the lab
  // polynomial's own error, modelled in SG#3 but not claimed, as for scale_factor.
  LabQuadratic loose = lab;
  loose.c2_sigma << 0.0, 0.0, c2 / 2.0;
  q.in.priors[Sensor::gyro].lab_quadratic = loose;
  const DiagnosisResult within_lab = diagnose(q.in);
  EXPECT_EQ(k2Of(within_lab, "k2"), nullptr) << diagnosisMarkdown(within_lab);
  EXPECT_TRUE(hasNote(within_lab, "scale_nonlinearity", "calibration error"))
      << diagnosisMarkdown(within_lab);
  // The sensor's bend is what SG#2 grafts: reported as already in the simulation.
  ASSERT_EQ(within_lab.in_simulation.size(), 1u) << diagnosisMarkdown(within_lab);
  const Effect& lab_term = within_lab.in_simulation[0];
  EXPECT_EQ(lab_term.name, "scale_nonlinearity");
  EXPECT_EQ(lab_term.sensor, "gyro");
  ASSERT_EQ(lab_term.parameters.size(), 1u);
  EXPECT_EQ(lab_term.parameters[0].values[2], c2);
  EXPECT_EQ(lab_term.parameters[0].sigma[2], c2 / 2.0);
  EXPECT_TRUE(std::isnan(lab_term.parameters[0].sigma[0]));  // a line on x: no k2 estimated
  const nlohmann::json lab_json =
      nlohmann::json::parse(diagnosisJson(within_lab)).at("modelled_in_simulation");
  ASSERT_EQ(lab_json.size(), 1u);
  EXPECT_EQ(lab_json[0].at("parameters").at("k2")[2].get<double>(), c2);
  EXPECT_TRUE(lab_json[0].at("uncertainty").at("k2")[0].is_null());
  EXPECT_NE(diagnosisMarkdown(within_lab).find("Already in the simulation"), std::string::npos);
  EXPECT_LT(within_lab.rms_after.gyro(2), 0.96 * within_lab.rms_before.gyro(2))
      << "modelled in SG#3\n" << diagnosisMarkdown(within_lab);
}

// An accelerometer-only rotation of its cross-axis terms (what a lab calibration error of the
// antisymmetric part looks like) within the lab's stated uncertainty is not a mounting
// misalignment; a real mounting rotation of both sensors, well beyond it, still is.
TEST(MismatchDiagnosis, MisalignmentWithinTheLabRotationUncertaintyIsNotClaimed) {
  const Eigen::Matrix3d lab_gyro_sigma = Eigen::Matrix3d::Constant(2e-4);
  const Eigen::Matrix3d lab_accel_sigma = Eigen::Matrix3d::Constant(1e-3);
  {
    ImuErrorModel extra;  // accel triad rotated by 1.5e-3 rad about z and 1e-3 about x
    extra.accel.non_orthogonality.N(0, 1) = -1.5e-3;
    extra.accel.non_orthogonality.N(1, 0) = 1.5e-3;
    extra.accel.non_orthogonality.N(1, 2) = -1e-3;
    extra.accel.non_orthogonality.N(2, 1) = 1e-3;
    Pair p = makePair(extra, 11);
    const DiagnosisResult without_lab = diagnose(p.in);
    // Ungated, the rotation shows: as a mounting rotation or (what it is) an accel cross-axis term.
    const Effect* n_accel = findEffect(without_lab, "non_orthogonality");
    ASSERT_TRUE(findEffect(without_lab, "mounting_misalignment") != nullptr ||
                (n_accel != nullptr && n_accel->sensor == "accel"))
        << "the case must show a rotation when nothing gates it\n" << diagnosisMarkdown(without_lab);
    p.in.priors[Sensor::gyro].lab_M_sigma = lab_gyro_sigma;
    p.in.priors[Sensor::accel].lab_M_sigma = lab_accel_sigma;
    const DiagnosisResult r = diagnose(p.in);
    EXPECT_TRUE(r.effects.empty()) << diagnosisMarkdown(r);
  }
  {
    ImuErrorModel extra;  // a mounting rotation of 1e-2 rad (0.57 deg), both sensors
    extra.mounting_misalignment.rotation_rad << 0.0, 4e-3, 1e-2;
    Pair p = makePair(extra, 12);
    p.in.priors[Sensor::gyro].lab_M_sigma = lab_gyro_sigma;
    p.in.priors[Sensor::accel].lab_M_sigma = lab_accel_sigma;
    const DiagnosisResult r = diagnose(p.in);
    const Effect* mm = findEffect(r, "mounting_misalignment");
    ASSERT_NE(mm, nullptr) << diagnosisMarkdown(r);
    EXPECT_NEAR(mm->parameters[0].values[2], 1e-2, std::max(3.0 * mm->parameters[0].sigma[2], 2e-3));
  }
}

// A mounting rotation of several degrees (as on the real car recording) is one rotation: its
// second order (here a gyro "scale factor" of up to -0.3 % and 0.2 % symmetric cross-axis terms
// under first-order columns) is modelled by linearizing at the first pass's rotation, so
// nothing else is named and the rotation is recovered.
TEST(MismatchDiagnosis, RotationOfSeveralDegreesIsNotSplitIntoScaleAndCrossAxisTerms) {
  ImuErrorModel extra;
  extra.mounting_misalignment.rotation_rad << -0.056, 0.022, 0.080;  // 5.6 deg
  Pair p = makePair(extra, 14);
  const DiagnosisResult r = diagnose(p.in);
  const Effect* mm = findEffect(r, "mounting_misalignment");
  ASSERT_NE(mm, nullptr) << diagnosisMarkdown(r);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(mm->parameters[0].values[a], extra.mounting_misalignment.rotation_rad(a),
                3.0 * mm->parameters[0].sigma[a]) << a << "\n" << diagnosisMarkdown(r);
  EXPECT_EQ(r.effects.size(), 1u) << diagnosisMarkdown(r);
  bool repeated = false;
  for (const std::string& n : r.notes) repeated |= n.find("linearized at the fitted rotation") != std::string::npos;
  EXPECT_TRUE(repeated);
}

// What the lab gates hold back is the lab calibration's own error: explained, so neither claimed
// nor listed as unexplained. Under common random numbers a null case listed 30-40 unexplained
// spans of 5e-5 m/s^2 in turns and braking: the lab's accelerometer cross-axis error.
TEST(MismatchDiagnosis, CalibrationErrorWithinTheLabUncertaintyIsNotUnexplained) {
  const Motion m = carMotion(23);
  const double T = 150.0;
  const ImuErrorModel noise = whiteNoise(3e-5, 3e-4);
  ImuErrorModel truth = noise;  // the lab's calibration error of the accelerometer triad
  truth.accel.scale_factor.k << 2e-3, -2e-3, 1e-3;
  truth.accel.non_orthogonality.N << 0.0, 3e-3, -2e-3, 2e-3, 0.0, 3e-3, -3e-3, 1e-3, 0.0;
  DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, T), truth, noise, 41,
                                     "reference + tested noise (as SG#2)");
  const DiagnosisResult ungated = diagnose(in);
  ASSERT_FALSE(ungated.effects.empty()) << "the error must show when nothing gates it";
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-4);
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(2e-3);  // 3 sigma = 6e-3: all within
  const DiagnosisResult r = diagnose(in);
  EXPECT_TRUE(r.effects.empty()) << diagnosisMarkdown(r);
  EXPECT_TRUE(r.unexplained.empty()) << diagnosisMarkdown(r);
}

// A gated term is the lab's calibration error: not claimed, but its signal is still in the
// residual. A claimed term whose regressor shares part of it must be fitted with it in the model.
// Here the lateral specific force carries 10 m/s x omega_z (a car at 10 m/s), so a gyro z scale
// error within the lab's uncertainty and a g-sensitivity G_zy (gyro z per f_y) overlap. Fitted
// without the gated scale error, G_zy took up part of it: 2.8e-4 for 2e-4, 74 sigma off. (Under
// common random numbers the suite's g-sensitivity had RMS err/sigma 12-22, its vibration
// rectification 7.)
TEST(MismatchDiagnosis, ClaimedTermIsFittedNextToTheGatedCalibrationError) {
  Motion m = carMotion(29);
  for (const auto& w : m.waves[2]) m.waves[4].push_back({10.0 * w[0], w[1], w[2]});
  const double T = 150.0;
  const ImuErrorModel noise = whiteNoise(3e-5, 3e-4);
  ImuErrorModel truth = noise;
  truth.gyro.scale_factor.k << 1.5e-3, -1.5e-3, 1.5e-3;  // calibration error, within the lab's
  truth.g_sensitivity.G.setZero();  // rad/s per m/s^2 (41 and -31 deg/h per m/s^2)
  truth.g_sensitivity.G(2, 1) = 2e-4;
  truth.g_sensitivity.G(0, 0) = -1.5e-4;
  DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, T), truth, noise, 51,
                                     "reference + tested noise (as SG#2)");
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(2e-3);  // 3 sigma = 6e-3: k is within
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-4);
  const DiagnosisResult r = diagnose(in);
  const Effect* g = findEffect(r, "g_sensitivity");
  ASSERT_NE(g, nullptr) << diagnosisMarkdown(r);
  EXPECT_EQ(findEffect(r, "scale_factor"), nullptr) << diagnosisMarkdown(r);
  for (int k : {1 * 3 + 0, 2 * 3 + 1, 0}) {  // G_yx (zero), G_zy, G_xx
    const double want = truth.g_sensitivity.G(k / 3, k % 3);
    const double got = g->parameters[0].values[k], sd = g->parameters[0].sigma[k];
    EXPECT_LT(std::abs(got - want), 3.0 * sd)
        << "G[" << k << "] = " << got << " +- " << sd << ", injected " << want << "\n"
        << diagnosisMarkdown(r);
  }
}

// The simulation is built on the reference signal and so carries the reference IMU's own scale
// error: a gyro scale difference within the lab's and the reference's uncertainty (its profile)
// is not the tested IMU's missing physics. Under common random numbers a navigation-grade
// reference's 26 ppm was claimed on a null case. A claim of a few times that uncertainty says the
// reference may be in it (random_14_04 under common random numbers: -36 ppm on x, the reference
// having drawn +33.5 ppm, 3.35 x its stated 10 ppm).
TEST(MismatchDiagnosis, ScaleWithinTheReferenceImusOwnUncertaintyIsNotClaimed) {
  ImuErrorModel extra;
  extra.gyro.scale_factor.k << 2e-3, -2e-3, 2e-3;
  Pair p = makePair(extra, 13);
  p.in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  p.in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  // The claimed gyro scale_factor's explanation, nullopt when none is claimed.
  const auto claimedScale = [&](std::optional<double> ref_sigma) -> std::optional<std::string> {
    p.in.priors[Sensor::gyro].reference_scale_sigma = ref_sigma;
    const DiagnosisResult r = diagnose(p.in);
    for (const Effect& e : r.effects)
      if (e.name == "scale_factor" && e.sensor == "gyro") return e.explanation;
    return std::nullopt;
  };
  const std::string kRefShare = "the reference's own gain error";
  const std::optional<std::string> unknown = claimedScale(std::nullopt);
  ASSERT_TRUE(unknown) << "the scale must show when nothing gates it";
  EXPECT_EQ(unknown->find(kRefShare), std::string::npos);
  EXPECT_FALSE(claimedScale(1e-3));  // 2e-3 is within 3 sigma of the reference's 1e-3
  // Beyond 3 sigma of 5e-4 but only 4 x it: claimed, and the reader is told that the reference's
  // own scale error (which the simulation inherits) may be part of it.
  const std::optional<std::string> near = claimedScale(5e-4);
  ASSERT_TRUE(near);
  EXPECT_NE(near->find(kRefShare), std::string::npos) << *near;
  EXPECT_NE(near->find(" x the reference IMU's stated scale uncertainty (500 ppm"),
            std::string::npos) << *near;
  // Ten times the reference's uncertainty: the tested IMU's, no such remark.
  const std::optional<std::string> far = claimedScale(2e-4);
  ASSERT_TRUE(far);
  EXPECT_EQ(far->find(kRefShare), std::string::npos) << *far;
}

// SG#2 grafts the lab's quadratic c2; at the drive's mean input x0 its gain is c1 + 2 c2 x0, so the
// lab's c2 uncertainty is a gain uncertainty there (f_z ~ -g: 2 g sigma_c2). A c2_z 2 sigma off is
// calibration error, not a z scale factor (under common random numbers random_14_22 and 13_15
// claimed -6.3e-4 and -5.2e-4 once the lab's M_sigma no longer carried the curvature's misfit).
TEST(MismatchDiagnosis, ScaleWithinTheLabQuadraticsUncertaintyAtTheMeanInputIsNotClaimed) {
  const Motion m = carMotion(31);
  const double T = 150.0, k2_z = 1e-4, c2_sigma = 1.5e-5;
  const ImuErrorModel noise = whiteNoise(3e-5, 1e-4);
  ImuErrorModel truth = noise, sg2 = noise;
  truth.accel.scale_nonlinearity.k2 << 0.0, 0.0, k2_z;
  sg2.accel.scale_nonlinearity.k2 << 0.0, 0.0, k2_z - 2.0 * c2_sigma;  // the lab's c2, 2 sigma off
  DiagnosisInputs in = graftedInputs(sampleMotion(m, 100.0, T), truth, sg2, 61,
                                     "reference + the lab's quadratic (as SG#2)");
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  const auto claimsScale = [&](double sigma) {
    LabQuadratic q;
    q.c2 << 0.0, 0.0, k2_z - 2.0 * c2_sigma;
    q.c2_sigma << 0.0, 0.0, sigma;
    in.priors[Sensor::accel].lab_quadratic = q;
    const DiagnosisResult r = diagnose(in);
    for (const Effect& e : r.effects)
      if ((e.name == "scale_factor" || e.name == "scale_nonlinearity") && e.sensor == "accel")
        return true;
    return false;
  };
  EXPECT_FALSE(claimsScale(c2_sigma));  // 2 g 2 sigma_c2: within 3 sigma of the lab's gain
  EXPECT_TRUE(claimsScale(0.1 * c2_sigma)) << "the gain difference must show when the lab is sure";
}

// A tested IMU with the response `sensor` whose tags are late by tau (the response applied to the
// motion measured at t - tau, exact), SG#2 as that response applied to the reference, all with
// white noise: seeds seed, seed + 1, seed + 2.
DiagnosisInputs lateResponseInputs(const Motion& m, double T, double tau,
                                   const ImuErrorModel& sensor, uint64_t seed) {
  const ImuErrorModel noise = whiteNoise(3e-5, 3e-4);
  ImuErrorModel truth = sensor;
  truth.gyro.white_noise = noise.gyro.white_noise;
  truth.accel.white_noise = noise.accel.white_noise;
  const ImuSeries late = test::sampleIntegral([&](double t) { return m.integral(t - tau); }, 100.0,
                                              T, 5000.0);
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.simulation_kind = "lab response applied to the reference (as SG#2)";
  in.reference = applyErrors(sampleMotion(m, 100.0, T), noise, seed);
  in.real = applyErrors(late, truth, seed + 1);
  in.simulated = applyErrors(in.reference, sensor, seed + 2);
  return in;
}

// The tested IMU applies its scale and cross-axis matrix M to the motion it measured at t - tau,
// and SG#2 applies the lab's M to x(t): the time offset's signal is M (x(t - tau) - x(t)). Shifting
// the bare reference left (M - I)(x(t - tau) - x(t)) in the residual, which other terms took up
// (under common random numbers g_sensitivity on 5 of 5 time-offset runs). Here M is large (2 %)
// so that the leftover shows with ordinary noise.
TEST(MismatchDiagnosis, TimeOffsetShiftsTheLabCalibratedResponse) {
  const Motion m = carMotion(21);
  const double T = 150.0, tau = 0.03;
  ImuErrorModel sensor;  // the tested IMU's linear response, which the lab calibrates
  sensor.gyro.scale_factor.k << 0.02, -0.02, 0.02;
  sensor.gyro.non_orthogonality.N << 0.0, 0.01, -0.01, 0.01, 0.0, 0.01, -0.01, 0.01, 0.0;
  const DiagnosisInputs in = lateResponseInputs(m, T, tau, sensor, 31);
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() +
                            sensor.gyro.non_orthogonality.N +
                            Eigen::Matrix3d(sensor.gyro.scale_factor.k.asDiagonal());
  const auto run = [&](bool with_M) {
    DiagnosisInputs x = in;
    if (with_M) x.priors[Sensor::gyro].lab_M = M;
    return diagnose(x);
  };
  // With the response shifted, only the offset is named and it is 14 us off (3.1 sigma; what is
  // left was not traced); shifting the bare reference it is 50 us off (6.4 sigma).
  const DiagnosisResult r = run(true);
  ASSERT_EQ(r.effects.size(), 1u) << diagnosisMarkdown(r);
  EXPECT_EQ(r.effects[0].name, "time_offset");
  const DiagnosisResult bare = run(false);
  const Effect* to = findEffect(bare, "time_offset");
  ASSERT_NE(to, nullptr);
  const double err = std::abs(r.effects[0].parameters[0].values[0] - tau);
  const double err_bare = std::abs(to->parameters[0].values[0] - tau);
  EXPECT_GT(err_bare, 3.0 * to->parameters[0].sigma[0]) << diagnosisMarkdown(bare);
  EXPECT_LT(err, 0.5 * err_bare);
}

// The same for the lab's quadratic: the tested accelerometer bends (c2_z, here 2e-3 per m/s^2,
// a slope 2 c2_z f_z of -4 % at f_z ~ -g), SG#2 carries the lab's c2, and the time offset's
// signal on z is that slope times f_z(t - tau) - f_z(t). Shifting M x alone (before) left the
// slope's part in the residual: here tau came out 50 us off (6.5 sigma; now 0.1 sigma), and on a
// random case with a 20-ms offset on road vibration it was claimed as a -0.5 % z scale factor
// (random_15_18).
TEST(MismatchDiagnosis, TimeOffsetShiftsTheLabQuadratic) {
  const Motion m = carMotion(23);
  const double T = 150.0, tau = 0.03;
  ImuErrorModel sensor;
  sensor.accel.scale_nonlinearity.k2 << 0.0, 0.0, 2e-3;
  DiagnosisInputs in = lateResponseInputs(m, T, tau, sensor, 41);
  in.priors[Sensor::accel].lab_M = Eigen::Matrix3d::Identity();
  LabQuadratic q;
  q.c2 = sensor.accel.scale_nonlinearity.k2;
  q.c2_sigma << 0.0, 0.0, 1e-6;
  in.priors[Sensor::accel].lab_quadratic = q;
  const DiagnosisResult r = diagnose(in);
  ASSERT_EQ(r.effects.size(), 1u) << diagnosisMarkdown(r);
  EXPECT_EQ(r.effects[0].name, "time_offset");
  EXPECT_LT(std::abs(r.effects[0].parameters[0].values[0] - tau),
            3.0 * r.effects[0].parameters[0].sigma[0]);
}

// Road vibration decorrelates within milliseconds: with a 4-ms offset the tested IMU's lever-arm
// signal at 25-35 Hz is the reference's angular acceleration at t - tau, not at t. Built at t
// (before commit dedf77a) the lever arm came out short (random_11_11: 6 % at 23 sigma).
// Car waves after a 10-s stop plus 0.01-rad/s gyro vibration at 25/30/35 Hz, faded in over 5 s,
// sampled at 200 Hz with tags late by `shift` and a lever arm r integrated exactly (16-node
// Gauss-Legendre on the rates and the centripetal term, the tangential term from the edge rates).
struct VibratingCar {
  Motion car = carMotion(5);
  double T = 120.0, rate_hz = 200.0, t0 = 5000.0;
  double accel_vibration_m_s2 = 0.0;  // amplitude of the specific force's road vibration
  Vector6d rate(double t) const {
    const double vib_hz[3] = {25.0, 30.0, 35.0};
    Vector6d w = car.offset;
    const double env = t < 10.0 ? 0.0 : t > 15.0 ? 1.0 : 0.5 - 0.5 * std::cos(M_PI * (t - 10.0) / 5.0);
    for (int c = 0; c < 6; ++c)
      for (const auto& wave : car.waves[c]) w(c) += env * wave[0] * std::sin(wave[1] * t + wave[2]);
    for (int c = 0; c < 3; ++c) w(c) += env * 0.01 * std::sin(2.0 * M_PI * vib_hz[c] * t + c);
    for (int c = 0; c < 3; ++c)
      w(3 + c) += env * accel_vibration_m_s2 * std::sin(2.0 * M_PI * (vib_hz[c] + 2.0) * t + 2 * c);
    return w;
  }
  ImuSeries sample(double shift, const Eigen::Vector3d& r) const {
    const GaussLegendreRule gl = gaussLegendreRule(16);
    ImuSeries out;
    for (int k = 1; k <= static_cast<int>(T * rate_hz); ++k) {
      const double a = (k - 1) / rate_hz - shift, b = k / rate_hz - shift;
      Vector6d inc = Vector6d::Zero();
      Eigen::Vector3d centripetal = Eigen::Vector3d::Zero();
      for (std::size_t i = 0; i < gl.nodes.size(); ++i) {
        const Vector6d w = rate(0.5 * (a + b) + 0.5 * (b - a) * gl.nodes[i]);
        inc += gl.weights[i] * w;
        const Eigen::Vector3d om = w.head<3>();
        centripetal += gl.weights[i] * om.cross(om.cross(r));
      }
      ImuSample smp;
      smp.t_s = t0 + k / rate_hz;
      smp.dt_s = 1.0 / rate_hz;
      smp.dtheta_rad = 0.5 * (b - a) * inc.head<3>();
      smp.dvel_m_s = 0.5 * (b - a) * (inc.tail<3>() + centripetal) +
                     (rate(b).head<3>() - rate(a).head<3>()).cross(r);
      out.push_back(smp);
    }
    return out;
  }
};

// A tested accelerometer r away from the reference rectifies the vibration it feels, which
// includes omega_dot x r of the road's angular vibration (here 0.01 rad/s at 25-35 Hz: about
// 0.6 m/s^2 at 0.3 m, next to 0.5 m/s^2 of linear vibration). Measured on the reference's
// specific force alone, the coefficient was off: here 1.9-2.4 % (1.4 sigma: the vibration is
// steady, so the missing power mostly goes into the bias), on random_20_15, whose vibration
// grows with speed, 23 % (6 sigma). With the level recomputed at the fitted lever arm: 0.15 %,
// sigma 10 x smaller.
TEST(MismatchDiagnosis, VibrationLevelIsTakenAtTheTestedImu) {
  VibratingCar car;
  car.accel_vibration_m_s2 = 0.5;
  const Eigen::Vector3d r(0.3, -0.2, 0.25);
  const Eigen::Vector3d coeff(0.02, -0.015, 0.02);
  const ImuErrorModel noise = whiteNoise(3e-5, 3e-4);
  ImuErrorModel truth = noise;
  truth.accel.vibration_rectification.coeff = coeff;
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.simulation_kind = "reference with white noise";
  in.reference = car.sample(0.0, Eigen::Vector3d::Zero());
  in.real = applyErrors(car.sample(0.0, r), truth, 91);
  in.simulated = applyErrors(in.reference, noise, 92);
  const DiagnosisResult d = diagnose(in);
  const Effect* vib = findEffect(d, "vibration_rectification");
  ASSERT_NE(findEffect(d, "lever_arm"), nullptr) << diagnosisMarkdown(d);
  ASSERT_NE(vib, nullptr) << diagnosisMarkdown(d);
  for (int a = 0; a < 3; ++a) {
    const double err = std::abs(vib->parameters[0].values[a] - coeff(a));
    EXPECT_LT(err, 3.0 * vib->parameters[0].sigma[a]) << "axis " << a;
    EXPECT_LT(err, 5e-3 * std::abs(coeff(a))) << "axis " << a << "\n" << diagnosisMarkdown(d);
  }
}

// A sensor bends each sample: under road vibration the bin mean of |f| is not |bin mean of f|
// (about a small f0 with vibration amplitude A it is ~ 2 A / pi + f0^2 / (pi A)). Built from the
// bin means, the asymmetry regressor left a quadratic and a vibration-power part in the residual,
// which scale_nonlinearity and vibration_rectification took up (under common random numbers on
// random_14_26, 14_12, 13_11). The regressors are the bin means of |f| and f^2 per sample.
TEST(MismatchDiagnosis, AsymmetryUnderVibrationIsMeasuredOnTheSamples) {
  VibratingCar car;
  car.accel_vibration_m_s2 = 0.6;
  const Eigen::Vector3d k_pos(6e-3, -5e-3, 0.0);
  const ImuSeries ideal = car.sample(0.0, Eigen::Vector3d::Zero());
  const ImuErrorModel noise = whiteNoise(3e-5, 1e-4);
  ImuErrorModel truth = noise, sg2 = noise;
  truth.accel.scale_asymmetry.k_pos = k_pos;
  truth.accel.scale_asymmetry.k_neg.setZero();
  sg2.accel.scale_factor.k = 0.5 * k_pos;  // the lab's line: the mean gain
  DiagnosisInputs in = graftedInputs(ideal, truth, sg2, 81, "reference + the lab's line (as SG#2)");
  in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
  const DiagnosisResult r = diagnose(in);
  EXPECT_EQ(findEffect(r, "scale_nonlinearity"), nullptr) << diagnosisMarkdown(r);
  EXPECT_EQ(findEffect(r, "vibration_rectification"), nullptr) << diagnosisMarkdown(r);
  const Effect* sa = findEffect(r, "scale_asymmetry");
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(r);
  for (int a = 0; a < 2; ++a) {
    const double d = sa->parameters[0].values[a] - sa->parameters[1].values[a];
    const double sd = std::hypot(sa->parameters[0].sigma[a], sa->parameters[1].sigma[a]);
    EXPECT_NEAR(d, k_pos(a), 3.0 * sd) << "axis " << a << "\n" << diagnosisMarkdown(r);
  }
}

TEST(MismatchDiagnosis, LeverArmUnderVibrationWithATimeOffset) {
  const VibratingCar car;
  const double tau = 0.004;
  const Eigen::Vector3d r_m(0.3, -0.2, 0.25);
  ImuErrorModel ref_noise, tested;
  ref_noise.gyro.white_noise.density.setConstant(1e-5);
  ref_noise.accel.white_noise.density.setConstant(1e-4);
  tested.gyro.white_noise.density.setConstant(3e-4);
  tested.accel.white_noise.density.setConstant(3e-3);
  tested.gyro.constant_bias.b << 0.01, -0.015, 0.005;
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.simulation_kind = "reference + static bias";
  in.reference = applyErrors(car.sample(0.0, Eigen::Vector3d::Zero()), ref_noise, 41);
  in.real = applyErrors(car.sample(tau, r_m), tested, 42);
  in.simulated = simulateFromReferenceAndStaticBias(in.reference, in.real).simulated;
  const DiagnosisResult res = diagnose(in);
  const Effect* la = findEffect(res, "lever_arm");
  ASSERT_NE(la, nullptr) << diagnosisMarkdown(res);
  ASSERT_NE(findEffect(res, "time_offset"), nullptr) << diagnosisMarkdown(res);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(la->parameters[0].values[a], r_m(a), 3.0 * la->parameters[0].sigma[a])
        << "axis " << a << "\n" << diagnosisMarkdown(res);
}

// A rectified vibration bias follows the vibration level, which follows speed: a slow regressor.
// Next to it, the tested accelerometer's bias random-walks (a realization the simulation does not
// share; the lab figures say so). The selection fits such a term by GLS, weighing each time scale
// against its own noise; the Ceres joint fit of the time offset whitens AR(1) only. Reporting
// the joint fit's parameters, 5 of the 12 coefficients below were beyond 3 sigma (worst 7.8; a
// random suite case 5-16 sigma); taking only the offset from the joint fit, none (worst 2.8).
TEST(MismatchDiagnosis, SlowRegressorNextToATimeOffsetKeepsItsGlsFit) {
  int outside = 0, found = 0;
  double worst = 0.0;
  for (uint64_t seed : {41u, 42u, 43u, 44u}) {
    ImuErrorModel extra;
    extra.time_offset.tau_s = 0.002;
    extra.accel.vibration_rectification.coeff << 0.02, -0.015, 0.01;
    extra.accel.bias_random_walk.density.setConstant(1e-3);
    Pair p = makePair(extra, seed);
    LabNoiseFigures lab;
    lab.rate_random_walk.setConstant(1e-3);
    p.in.priors[Sensor::accel].lab_noise = lab;
    const DiagnosisResult r = diagnose(p.in);
    ASSERT_NE(findEffect(r, "time_offset"), nullptr) << diagnosisMarkdown(r);
    const Effect* vr = findEffect(r, "vibration_rectification");
    if (vr == nullptr || vr->sensor != "accel") continue;
    ++found;
    for (int a = 0; a < 3; ++a) {
      const double z = std::abs(vr->parameters[0].values[a] - extra.accel.vibration_rectification.coeff(a)) /
                       vr->parameters[0].sigma[a];
      worst = std::max(worst, z);
      outside += z > 3.0;
    }
  }
  EXPECT_GE(found, 3);
  EXPECT_LE(outside, 1) << "worst " << worst << " sigma";
}

// The lever arm's acceleration reaches the tested output through the sensor's response: with a
// quadratic c2 the slope is 1 + 2 c2 f, and f_z ~ -g makes a c2_z of 8e-4 per m/s^2 scale the z
// acceleration by -1.6 %. SG#2 grafts c2 on the reference's f only. A random case (tactical,
// 200 Hz, vibration, c2 from the lab) came out with r_m 1.2 / 1.9 % short at 10 / 5 sigma.
TEST(MismatchDiagnosis, LeverArmPassesThroughTheLabCalibratedQuadratic) {
  const VibratingCar car;
  const Eigen::Vector3d r_m(0.19, -0.04, -0.06);
  ImuErrorModel ref_noise, quadratic, tested;
  ref_noise.gyro.white_noise.density.setConstant(1e-5);
  ref_noise.accel.white_noise.density.setConstant(1e-4);
  quadratic.accel.scale_nonlinearity.k2 << -6.7e-4, -2e-4, 8e-4;
  tested = quadratic;
  tested.gyro.white_noise.density.setConstant(3e-5);
  tested.accel.white_noise.density.setConstant(3e-4);
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.simulation_kind = "reference through the lab's quadratic (as SG#2)";
  in.reference = applyErrors(car.sample(0.0, Eigen::Vector3d::Zero()), ref_noise, 51);
  in.real = applyErrors(car.sample(0.0, r_m), tested, 52);
  in.simulated = applyErrors(in.reference, quadratic, 0);
  const auto worstSigma = [&](bool with_lab_quadratic) {
    DiagnosisInputs x = in;
    if (with_lab_quadratic) x.priors[Sensor::accel].lab_quadratic = LabQuadratic{quadratic.accel.scale_nonlinearity.k2,
                                                                 Eigen::Vector3d::Zero()};
    const DiagnosisResult res = diagnose(x);
    const Effect* la = findEffect(res, "lever_arm");
    EXPECT_NE(la, nullptr) << diagnosisMarkdown(res);
    double worst = 0.0;
    for (int a = 0; la && a < 3; ++a)
      worst = std::max(worst, std::abs(la->parameters[0].values[a] - r_m(a)) /
                                  la->parameters[0].sigma[a]);
    return worst;
  };
  EXPECT_LT(worstSigma(true), 3.0);
  EXPECT_GT(worstSigma(false), 3.0) << "without the response the lever arm must come out short";
}

TEST(MismatchDiagnosis, QuantizationFoundFromTheValueLattice) {
  ImuErrorModel extra;
  extra.accel.quantization.step.setConstant(2e-3);  // m/s per increment
  const Pair p = makePair(extra, 4);
  const Eigen::Vector3d q = detectQuantizationStep(p.in.real, false);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(q(a), 2e-3, 1e-9);
  EXPECT_EQ(detectQuantizationStep(p.in.real, true), Eigen::Vector3d::Zero());
  const DiagnosisResult r = diagnose(p.in);
  const Effect* e = findEffect(r, "quantization");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->sensor, "accel");
}

// A field that runs colder than the lab: the simulation's bias is the lab's, at 25 degC, and the
// tested gyro's bias follows its temperature (7 -> 16 degC here). The residual's constant is
// the nuisance's, so the term is found from the warm-up alone; but its mean, per_degC times
// (T - 25), is physics SG#3 must carry (random_40_17: 55 deg/h of gyro z, heading DIFF 64 -> 33 %
// over 10 seeds). Before, SG#3 grafted the warm-up's variation only and t_ref_degC was the
// field's mean temperature.
TEST(MismatchDiagnosis, TemperatureBiasIsGraftedWithItsOffsetFromTheSimulationsTemperature) {
  const double duration_s = 300.0, lab_degC = 25.0;
  ImuSeries reference = sampleMotion(carMotion(41), 100.0, duration_s);
  const double t0 = reference.front().t_s;
  const auto field_degC = [&](double t) { return 16.0 - 9.0 * std::exp(-(t - t0) / 120.0); };
  ImuSeries field = reference, lab = reference;
  for (ImuSample& smp : field) smp.temperature_degC = field_degC(smp.t_s);
  for (ImuSample& smp : lab) smp.temperature_degC = lab_degC;
  // Tactical-grade white noise and no bias wander, so the slow-noise check is off: this test
  // is about what SG#3 grafts, not about telling a warm-up from a wander.
  const ImuErrorModel noise = whiteNoise(3e-5, 3e-4);
  ImuErrorModel real = noise;
  real.gyro.temperature_bias.per_degC << 2e-5, -4e-5, 3e-5;  // 4-8 deg/h per degC
  real.gyro.temperature_bias.t_ref_degC = lab_degC;
  DiagnosisInputs in = graftedInputs(field, real, noise, 43, "SG#2 (lab at 25 degC)");
  in.reference = reference;  // the reference IMU has no temperature column
  in.simulated = applyErrors(lab, noise, 44);
  DiagnoseOptions opt;
  opt.slow_block_s = 0.0;
  const DiagnosisResult r = diagnose(in, opt);
  const Effect* e = findEffect(r, "temperature_bias");
  ASSERT_NE(e, nullptr) << diagnosisJson(r);
  ASSERT_EQ(e->sensor, "gyro");
  const EffectParameter* k = nullptr;
  const EffectParameter* t_ref = nullptr;
  for (const EffectParameter& p : e->parameters) {
    if (p.key == "per_degC") k = &p;
    if (p.key == "t_ref_degC") t_ref = &p;
  }
  ASSERT_NE(k, nullptr);
  ASSERT_NE(t_ref, nullptr);
  EXPECT_NEAR(t_ref->values[0], lab_degC, 1e-9);
  // SG#3 minus the simulation, per axis, against per_degC (mean T - 25): the offset the fitted
  // coefficient implies, and the true one within that coefficient's 3 sigma.
  double mean_dT = 0.0;
  Eigen::Vector3d sg3_minus_sim = Eigen::Vector3d::Zero();
  ASSERT_EQ(r.sg3.size(), in.simulated.size());
  for (std::size_t i = 0; i < r.sg3.size(); ++i) {
    mean_dT += field_degC(in.simulated[i].t_s) - lab_degC;
    sg3_minus_sim += (r.sg3[i].dtheta_rad - in.simulated[i].dtheta_rad) / in.simulated[i].dt_s;
  }
  mean_dT /= static_cast<double>(r.sg3.size());
  sg3_minus_sim /= static_cast<double>(r.sg3.size());
  ASSERT_LT(mean_dT, -10.0);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(sg3_minus_sim(a), k->values[a] * mean_dT, 0.05 * std::abs(k->values[a] * mean_dT))
        << "axis " << a;
    EXPECT_NEAR(sg3_minus_sim(a), real.gyro.temperature_bias.per_degC(a) * mean_dT,
                3.0 * k->sigma[a] * std::abs(mean_dT) + 1e-6)
        << "axis " << a;
  }
}

// Without a lab, the simulation's bias is the tested IMU's over its first static span, so the
// temperature behind it is the tested IMU's there, not the reference IMU's (which a copy of the
// reference carried before: a temperature bias was then regressed on tested minus reference
// temperature).
TEST(MismatchDiagnosis, StaticBiasSimulationCarriesTheTestedTemperatureOfItsSpan) {
  ImuSeries reference = sampleMotion(carMotion(47), 100.0, 60.0);
  ImuSeries tested = reference;
  const double t0 = reference.front().t_s;
  for (ImuSample& smp : reference) smp.temperature_degC = 40.0;
  for (ImuSample& smp : tested) smp.temperature_degC = 10.0 + 0.1 * (smp.t_s - t0);
  const StaticBiasSimulation sim = simulateFromReferenceAndStaticBias(reference, tested);
  ASSERT_LT(sim.t_end_s, t0 + 20.0);  // the span is in the opening stop
  const double span_mid_degC = 10.0 + 0.1 * (0.5 * (sim.t_start_s + sim.t_end_s) - t0);
  EXPECT_NEAR(sim.temperature_degC, span_mid_degC, 0.06);
  for (const ImuSample& smp : sim.simulated) ASSERT_EQ(smp.temperature_degC, sim.temperature_degC);
  for (ImuSample& smp : tested) smp.temperature_degC = std::nan("");
  EXPECT_TRUE(std::isnan(simulateFromReferenceAndStaticBias(reference, tested).temperature_degC));
}

// diagnosis.json has exactly the keys and types of issue 7 item 5.
TEST(MismatchDiagnosis, JsonHasTheIssueShape) {
  ImuErrorModel extra;
  extra.time_offset.tau_s = -0.01;
  extra.mounting_misalignment.rotation_rad << 0.0, 0.01, -0.02;
  const Pair p = makePair(extra, 5);
  const DiagnosisResult r = diagnose(p.in);
  const nlohmann::json j = nlohmann::json::parse(diagnosisJson(r));
  ASSERT_TRUE(j.at("case").is_string());
  for (const char* list : {"located", "unexplained"}) {
    ASSERT_TRUE(j.at(list).is_array()) << list;
    for (const auto& s : j.at(list)) {
      EXPECT_TRUE(s.at("channel").is_string());
      EXPECT_TRUE(s.at("t_start").is_number());
      EXPECT_TRUE(s.at("t_end").is_number());
      EXPECT_TRUE(s.at("regime").is_string());
      EXPECT_TRUE(s.at("excess_rms").is_number());
    }
  }
  EXPECT_FALSE(j.at("located").empty());
  ASSERT_TRUE(j.at("effects").is_array());
  ASSERT_FALSE(j.at("effects").empty());
  const std::set<std::string> sensors = {"gyro", "accel", "both"};
  for (const auto& e : j.at("effects")) {
    EXPECT_TRUE(e.at("name").is_string());
    EXPECT_EQ(sensors.count(e.at("sensor").get<std::string>()), 1u);
    EXPECT_TRUE(e.at("parameters").is_object());
    EXPECT_TRUE(e.at("uncertainty").is_object());
    EXPECT_TRUE(e.at("evidence").at("delta_bic").is_number());
    EXPECT_TRUE(e.at("evidence").at("cv_gain").is_number());
    EXPECT_TRUE(e.at("explanation").is_string());
    if (e.at("name") == "time_offset") {
      EXPECT_TRUE(e.at("parameters").at("tau_s").is_number());
    }
    if (e.at("name") == "mounting_misalignment") {
      EXPECT_EQ(e.at("parameters").at("rotation_rad").size(), 3u);
    }
  }
  const auto& fit = j.at("fit");
  for (const char* k : {"signal_rms_before", "signal_rms_after"}) {
    EXPECT_EQ(fit.at(k).at("gyro").size(), 3u);
    EXPECT_EQ(fit.at(k).at("accel").size(), 3u);
  }
  EXPECT_TRUE(fit.contains("diff_before"));
  EXPECT_TRUE(fit.contains("diff_after"));
}

}  // namespace
}  // namespace graftnav
