// Mismatch finder end to end: gains per sign, the lab's quadratic, one-signed gains and the
// names of one even response.
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
#include "mismatch_diagnosis_fixture.h"

namespace graftnav {
namespace {

using namespace diagnosis_test;  // the shared fixtures of mismatch_diagnosis_fixture.h

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
  const Effect* sa = findEffect(r, TermKind::scale_asymmetry);
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(r);
  ASSERT_GE(sa->parameters.size(), 4u);
  EXPECT_EQ(sa->parameters[0].key, "k_pos");
  EXPECT_EQ(sa->parameters[1].key, "k_neg");
  EXPECT_EQ(sa->parameters[2].key, "k_pos_missing");
  const double d = sa->parameters[0].values[2] - sa->parameters[1].values[2];
  const double sd = std::hypot(sa->parameters[0].sigma[2], sa->parameters[1].sigma[2]);
  EXPECT_NEAR(d, 0.04, 3.0 * sd) << diagnosisMarkdown(r);
  EXPECT_EQ(findEffect(r, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(r);
}

// The gains per sign are reported relative to the simulation's linear gain: a tested gyro with a
// 0.2-0.3 % scale factor that the lab calibrated (SG#2 holds it) and a symmetric asymmetry +-d
// on z comes back as k_pos = +d, k_neg = -d element by element, not as the sensor's whole gains
// (scale factor +- d; reported as the whole gains, k_pos z was 0.007 here, 20 sigma off).
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
  const Effect* sa = findEffect(r, TermKind::scale_asymmetry);
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
  EXPECT_EQ(findEffect(r_off, TermKind::scale_factor), nullptr) << diagnosisMarkdown(r_off);
  const Effect* sa_off = findEffect(r_off, TermKind::scale_asymmetry);
  ASSERT_NE(sa_off, nullptr) << diagnosisMarkdown(r_off);
  EXPECT_GT(sa_off->parameters[0].values[2] + sa_off->parameters[1].values[2], 1e-3)
      << "the mean of the gains per sign holds the lab's error (2 x 1e-3 expected)";
  EXPECT_NEAR(sa_off->parameters[0].values[2], d, 3.0 * sa_off->parameters[0].sigma[2])
      << diagnosisMarkdown(r_off);
  EXPECT_NEAR(sa_off->parameters[1].values[2], -d, 3.0 * sa_off->parameters[1].sigma[2]);
}

// The asymmetry gate weighs the half-difference d of the gains per sign against what the lab
// can put there: not its gain (an error of it moves both gains alike; with 2 M_sigma^2 in the
// gate random_36_23's gyro asymmetry at 1.6 x its limit was held back), but the error of a
// quadratic it kept, which is even in x like |x|.
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
  const Effect* sa = findEffect(loose_gain, TermKind::scale_asymmetry);
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(loose_gain);
  EXPECT_NEAR(sa->parameters[0].values[2] - sa->parameters[1].values[2], 2.0 * d,
              3.0 * std::hypot(sa->parameters[0].sigma[2], sa->parameters[1].sigma[2]));

  // The lab kept a z quadratic (zero) to +-0.1 per rad/s: on this drive's yaw rates its error
  // reads on |x| as 0.37 rad/s x 0.1 = 0.037, nine times d. Not claimed, and said why.
  LabQuadratic lab;
  lab.c2_sigma << 0.0, 0.0, 0.1;
  in.priors[Sensor::gyro].lab_quadratic = lab;
  const DiagnosisResult loose_c2 = diagnose(in);
  EXPECT_EQ(findEffect(loose_c2, TermKind::scale_asymmetry), nullptr)
      << diagnosisMarkdown(loose_c2);
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
  EXPECT_EQ(findEffect(folded, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(folded);
  const Effect* sa = findEffect(folded, TermKind::scale_asymmetry);
  const Effect* sa_plain = findEffect(plain, TermKind::scale_asymmetry);
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
        << "axis " << a << "\n"
        << diagnosisMarkdown(folded);
  }
  // SG#3 takes the lab's quadratic out: it is no longer listed as in the simulation.
  for (const Effect& e : folded.in_simulation) EXPECT_NE(e.sensor, SensorScope::accel);
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
  const Effect* sa = findEffect(r, TermKind::scale_asymmetry);
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(r);
  EXPECT_NEAR(sa->parameters[0].values[0], d, 3.0 * sa->parameters[0].sigma[0])
      << diagnosisMarkdown(r);
  EXPECT_NEAR(sa->parameters[1].values[0], -d, 3.0 * sa->parameters[1].sigma[0]);
  EXPECT_LT(sa->parameters[0].sigma[0], 0.1 * d) << "x is determined";
  // The field does not claim the curvature here (MEMS noise): the lab's is what holds it.
  EXPECT_EQ(findEffect(r, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(r);
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
    DiagnosisInputs in =
        graftedInputs(reference, real, noise, 51, "reference + the lab's line (as SG#2)");
    in.priors[Sensor::gyro].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
    in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-6);
    LabQuadratic lab;  // lines on all axes; the degree-2 estimates the test dropped
    lab.c2_tested << 0.0, 0.0, c2_tested;
    lab.c2_tested_sigma << 2e-5, 2e-5, c2_tested_sigma;
    in.priors[Sensor::accel].lab_quadratic = lab;
    return diagnose(in);
  };
  const DiagnosisResult bent = run(true, 0.9 * k2, 2e-5);
  const Effect* nl = findEffect(bent, TermKind::scale_nonlinearity);
  ASSERT_NE(nl, nullptr) << diagnosisMarkdown(bent);
  EXPECT_EQ(nl->sensor, SensorScope::accel);
  EXPECT_EQ(findEffect(bent, TermKind::scale_factor), nullptr) << diagnosisMarkdown(bent);
  EXPECT_NEAR(nl->parameters[0].values[2], k2, 3.0 * nl->parameters[0].sigma[2])
      << diagnosisMarkdown(bent);
  EXPECT_LT(nl->parameters[0].sigma[2], 0.2 * std::abs(k2));

  const DiagnosisResult gain = run(false, 1e-6, 2e-5);
  const Effect* sf = findEffect(gain, TermKind::scale_factor);
  ASSERT_NE(sf, nullptr) << diagnosisMarkdown(gain);
  EXPECT_NEAR(sf->parameters[0].values[2], -2.0 * g * k2, 3.0 * sf->parameters[0].sigma[2]);
  EXPECT_EQ(findEffect(gain, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(gain);

  const DiagnosisResult coarse = run(true, 0.9 * k2, 3e-4);
  EXPECT_EQ(findEffect(coarse, TermKind::scale_factor), nullptr) << diagnosisMarkdown(coarse);
  EXPECT_EQ(findEffect(coarse, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(coarse);
  ASSERT_EQ(coarse.ambiguous.size(), 1u) << diagnosisMarkdown(coarse);
  EXPECT_EQ(coarse.ambiguous[0].alternative, &termSpec(TermKind::scale_nonlinearity));
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
      lab.c2(2) = 0.5 * a / g;                        // and its quadratic: d / g
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
  EXPECT_EQ(findEffect(folded, TermKind::scale_factor), nullptr) << diagnosisMarkdown(folded);
  const Effect* sa = findEffect(folded, TermKind::scale_asymmetry);
  ASSERT_NE(sa, nullptr) << diagnosisMarkdown(folded);
  EXPECT_EQ(sa->sensor, SensorScope::accel);
  // Gains per sign about the lab's mean gain: +-d on z, d = a / 2.
  EXPECT_NEAR(sa->parameters[0].values[2], -3e-3, 3.0 * sa->parameters[0].sigma[2])
      << diagnosisMarkdown(folded);
  EXPECT_NEAR(sa->parameters[1].values[2], 3e-3, 3.0 * sa->parameters[1].sigma[2]);
  EXPECT_LT(sa->parameters[0].sigma[2], 0.3 * 3e-3);

  const DiagnosisResult gain = run(false);
  EXPECT_EQ(findEffect(gain, TermKind::scale_factor), nullptr) << diagnosisMarkdown(gain);
  EXPECT_EQ(findEffect(gain, TermKind::scale_asymmetry), nullptr) << diagnosisMarkdown(gain);
  ASSERT_EQ(gain.ambiguous.size(), 1u) << diagnosisMarkdown(gain);
  EXPECT_EQ(gain.ambiguous[0].effect.kind(), TermKind::scale_factor);
  EXPECT_EQ(gain.ambiguous[0].alternative, &termSpec(TermKind::scale_asymmetry));
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
    EXPECT_EQ(findEffect(near, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(near);
    EXPECT_LT(near.rms_after.gyro(2), 0.99 * near.rms_before.gyro(2)) << "modelled in SG#3";
    if (findEffect(near, TermKind::scale_asymmetry) != nullptr) continue;
    ASSERT_EQ(near.ambiguous.size(), 1u) << diagnosisMarkdown(near);
    const AmbiguousEffect& a = near.ambiguous[0];
    ++ambiguous;
    EXPECT_EQ(a.effect.sensor, SensorScope::gyro);
    EXPECT_LT(a.name_margin, SelectionOptions{}.min_name_margin);
    const double for_abs =
        a.effect.kind() == TermKind::scale_asymmetry ? a.name_margin : -a.name_margin;
    EXPECT_GT(for_abs, 0.0) << "seed " << seed << "\n" << diagnosisMarkdown(near);
    const nlohmann::json j = nlohmann::json::parse(diagnosisJson(near));
    ASSERT_EQ(j["ambiguous"].size(), 1u);
    EXPECT_EQ(j["ambiguous"][0]["alternative"], a.alternative->name);
    EXPECT_TRUE(j["ambiguous"][0]["evidence"].contains("name_margin"));
  }
  EXPECT_GE(ambiguous, 1) << "0.0015 is meant to sit where the shape is not settled";
  // Each shape named when it fits clearly better.
  const DiagnosisResult asym = run(0.002, 0.0, 5), quad = run(0.0, 0.005, 5);
  EXPECT_NE(findEffect(asym, TermKind::scale_asymmetry), nullptr) << diagnosisMarkdown(asym);
  EXPECT_EQ(findEffect(asym, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(asym);
  EXPECT_TRUE(asym.ambiguous.empty()) << diagnosisMarkdown(asym);
  EXPECT_NE(findEffect(quad, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(quad);
  EXPECT_EQ(findEffect(quad, TermKind::scale_asymmetry), nullptr) << diagnosisMarkdown(quad);
  EXPECT_TRUE(quad.ambiguous.empty()) << diagnosisMarkdown(quad);
}

}  // namespace
}  // namespace graftnav
