// Mismatch finder end to end: the lab gates, calibration error that is not unexplained, and the
// time offset of the lab-calibrated response.
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
    const Effect* e = findEffect(r, TermKind::scale_nonlinearity);
    if (!e || e->sensor != SensorScope::gyro) return nullptr;
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
      << "the artefact stays in the model (SG#3)\n"
      << diagnosisMarkdown(artefact);

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
  EXPECT_EQ(lab_term.kind(), TermKind::scale_nonlinearity);
  EXPECT_EQ(lab_term.sensor, SensorScope::gyro);
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
      << "modelled in SG#3\n"
      << diagnosisMarkdown(within_lab);
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
    const Effect* n_accel = findEffect(without_lab, TermKind::non_orthogonality);
    ASSERT_TRUE(findEffect(without_lab, TermKind::mounting_misalignment) != nullptr ||
                (n_accel != nullptr && n_accel->sensor == SensorScope::accel))
        << "the case must show a rotation when nothing gates it\n"
        << diagnosisMarkdown(without_lab);
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
    const Effect* mm = findEffect(r, TermKind::mounting_misalignment);
    ASSERT_NE(mm, nullptr) << diagnosisMarkdown(r);
    EXPECT_NEAR(mm->parameters[0].values[2], 1e-2,
                std::max(3.0 * mm->parameters[0].sigma[2], 2e-3));
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
  const Effect* mm = findEffect(r, TermKind::mounting_misalignment);
  ASSERT_NE(mm, nullptr) << diagnosisMarkdown(r);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(mm->parameters[0].values[a], extra.mounting_misalignment.rotation_rad(a),
                3.0 * mm->parameters[0].sigma[a])
        << a << "\n"
        << diagnosisMarkdown(r);
  EXPECT_EQ(r.effects.size(), 1u) << diagnosisMarkdown(r);
  bool repeated = false;
  for (const std::string& n : r.notes)
    repeated |= n.find("linearized at the fitted rotation") != std::string::npos;
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
  in.priors[Sensor::accel].lab_M_sigma =
      Eigen::Matrix3d::Constant(2e-3);  // 3 sigma = 6e-3: all within
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
  in.priors[Sensor::gyro].lab_M_sigma =
      Eigen::Matrix3d::Constant(2e-3);  // 3 sigma = 6e-3: k is within
  in.priors[Sensor::accel].lab_M_sigma = Eigen::Matrix3d::Constant(1e-4);
  const DiagnosisResult r = diagnose(in);
  const Effect* g = findEffect(r, TermKind::g_sensitivity);
  ASSERT_NE(g, nullptr) << diagnosisMarkdown(r);
  EXPECT_EQ(findEffect(r, TermKind::scale_factor), nullptr) << diagnosisMarkdown(r);
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
      if (e.kind() == TermKind::scale_factor && e.sensor == SensorScope::gyro) return e.explanation;
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
            std::string::npos)
      << *near;
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
      if ((e.kind() == TermKind::scale_factor || e.kind() == TermKind::scale_nonlinearity) &&
          e.sensor == SensorScope::accel)
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
  const ImuSeries late =
      test::sampleIntegral([&](double t) { return m.integral(t - tau); }, 100.0, T, 5000.0);
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
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() + sensor.gyro.non_orthogonality.N +
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
  EXPECT_EQ(r.effects[0].kind(), TermKind::time_offset);
  const DiagnosisResult bare = run(false);
  const Effect* to = findEffect(bare, TermKind::time_offset);
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
  EXPECT_EQ(r.effects[0].kind(), TermKind::time_offset);
  EXPECT_LT(std::abs(r.effects[0].parameters[0].values[0] - tau),
            3.0 * r.effects[0].parameters[0].sigma[0]);
}

}  // namespace
}  // namespace graftnav
