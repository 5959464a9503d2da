// Mismatch finder end to end under road vibration: the vibration level and g-sensitivity at the
// tested IMU, even shapes on the samples, the lever arm with a time offset and through the lab's
// quadratic.
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
    const double env = t < 10.0   ? 0.0
                       : t > 15.0 ? 1.0
                                  : 0.5 - 0.5 * std::cos(M_PI * (t - 10.0) / 5.0);
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
  const Effect* vib = findEffect(d, TermKind::vibration_rectification);
  ASSERT_NE(findEffect(d, TermKind::lever_arm), nullptr) << diagnosisMarkdown(d);
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
  EXPECT_EQ(findEffect(r, TermKind::scale_nonlinearity), nullptr) << diagnosisMarkdown(r);
  EXPECT_EQ(findEffect(r, TermKind::vibration_rectification), nullptr) << diagnosisMarkdown(r);
  const Effect* sa = findEffect(r, TermKind::scale_asymmetry);
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
  const Effect* la = findEffect(res, TermKind::lever_arm);
  ASSERT_NE(la, nullptr) << diagnosisMarkdown(res);
  ASSERT_NE(findEffect(res, TermKind::time_offset), nullptr) << diagnosisMarkdown(res);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(la->parameters[0].values[a], r_m(a), 3.0 * la->parameters[0].sigma[a])
        << "axis " << a << "\n"
        << diagnosisMarkdown(res);
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
    ASSERT_NE(findEffect(r, TermKind::time_offset), nullptr) << diagnosisMarkdown(r);
    const Effect* vr = findEffect(r, TermKind::vibration_rectification);
    if (vr == nullptr || vr->sensor != SensorScope::accel) continue;
    ++found;
    for (int a = 0; a < 3; ++a) {
      const double z =
          std::abs(vr->parameters[0].values[a] - extra.accel.vibration_rectification.coeff(a)) /
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
    if (with_lab_quadratic)
      x.priors[Sensor::accel].lab_quadratic =
          LabQuadratic{quadratic.accel.scale_nonlinearity.k2, Eigen::Vector3d::Zero()};
    const DiagnosisResult res = diagnose(x);
    const Effect* la = findEffect(res, TermKind::lever_arm);
    EXPECT_NE(la, nullptr) << diagnosisMarkdown(res);
    double worst = 0.0;
    for (int a = 0; la && a < 3; ++a)
      worst = std::max(worst,
                       std::abs(la->parameters[0].values[a] - r_m(a)) / la->parameters[0].sigma[a]);
    return worst;
  };
  EXPECT_LT(worstSigma(true), 3.0);
  EXPECT_GT(worstSigma(false), 3.0) << "without the response the lever arm must come out short";
}

}  // namespace
}  // namespace graftnav
