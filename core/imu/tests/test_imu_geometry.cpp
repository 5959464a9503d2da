// The field-mounting geometry (applyGeometry): time offset, lever arm and mounting misalignment
// against their analytic effects on exactly integrated increments.
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

// ---- geometry ---------------------------------------------------------------------------

TEST(ImuErrorModel, TimeOffsetOnASinusoidMatchesTheShiftedIntegral) {
  // omega(t) = c + A sin(2 pi f t), f(t) = c' + B cos(2 pi f t): exact integrals are known, so
  // the sample tagged [t-dt, t] must equal the integral over [t-dt-tau, t-tau].
  const double A = 0.8, B = 3.0, freq = 1.3;
  const double w = 2.0 * kPi * freq;
  const IntervalFn gyro = [&](double a, double b) {
    const double v = A * (std::cos(w * a) - std::cos(w * b)) / w;
    return Vector3d(v + 0.1 * (b - a), -v, 0.5 * v);
  };
  const IntervalFn accel = [&](double a, double b) {
    const double v = B * (std::sin(w * b) - std::sin(w * a)) / w;
    return Vector3d(v, 2.0 * v, -9.8 * (b - a) + v);
  };
  for (double dt : {0.01, 0.005}) {
    const ImuSeries in = makeSeries(static_cast<int>(20.0 / dt), dt, gyro, accel);
    for (double tau : {0.0037, -0.0123, 0.02}) {
      ImuErrorModel m;
      m.time_offset.tau_s = tau;
      const ImuSeries out = applyErrors(in, m, 1);
      double max_err = 0.0, max_shift_effect = 0.0;
      // Interior samples (the first/last 3 use one-sided rate estimates and end extrapolation).
      for (size_t k = 5; k + 5 < in.size(); ++k) {
        const double t1 = in[k].t_s, t0 = t1 - dt;
        const Vector3d eg = out[k].dtheta_rad - gyro(t0 - tau, t1 - tau);
        const Vector3d ea = out[k].dvel_m_s - accel(t0 - tau, t1 - tau);
        max_err = std::max({max_err, eg.cwiseAbs().maxCoeff(), ea.cwiseAbs().maxCoeff() / 4.0});
        max_shift_effect =
            std::max(max_shift_effect, (out[k].dtheta_rad - in[k].dtheta_rad).norm());
      }
      // Cubic Hermite error bound h^4/384 |Theta''''| = h^4/384 A w^3 at each end, counted twice
      // without cancellation (tol = h^4 A w^3 / 100 > 2 h^4 A w^3 / 384); the shift itself is
      // ~ A w tau dt >= 1e-4 rad, so this separates right from wrong (or wrong-signed) shifts.
      const double tol = std::pow(dt, 4) * A * w * w * w / 100.0;
      EXPECT_LT(max_err, tol) << "dt " << dt << " tau " << tau;
      EXPECT_GT(max_shift_effect, 1e-5) << "dt " << dt << " tau " << tau;
    }
  }
}

TEST(ImuErrorModel, TimeOffsetPreservesTheIntegralOfAnArbitrarySignal) {
  // Interpolating the cumulative sum telescopes: the sum of the shifted increments equals the
  // cumulative sum at the shifted end points. With a cubic rate the 5-point slopes are exact
  // and the cubic Hermite error is h^4/384 |Theta''''| ~ 6e-14, so the shifted increments match
  // the exact ones to rounding, several samples away from the tag.
  const IntervalFn cubic = [](double a, double b) {
    auto F = [](double t) {
      t -= 1000.0;
      return 0.3 * t + 0.02 * t * t - 0.004 * t * t * t + 1e-4 * t * t * t * t;
    };
    return Vector3d(F(b) - F(a), 2.0 * (F(b) - F(a)), -(F(b) - F(a)));
  };
  const double dt = 0.01;
  const ImuSeries in = makeSeries(1000, dt, cubic, cubic);
  ImuErrorModel m;
  m.time_offset.tau_s = 0.0531;  // 5.31 samples
  const ImuSeries out = applyErrors(in, m, 1);
  for (size_t k = 10; k + 10 < in.size(); ++k) {
    const double t1 = in[k].t_s;
    EXPECT_LT((out[k].dtheta_rad - cubic(t1 - dt - 0.0531, t1 - 0.0531)).norm(), 1e-12);
  }
}

TEST(ImuErrorModel, LeverArmOnConstantRotationGivesCentripetalForce) {
  ImuErrorModel m;
  m.lever_arm.r_m = Vector3d(0.4, -0.25, 0.9);
  const double dt = 0.005;
  const ImuSeries in = constantSeries(200, dt, kOmega, kF);
  const ImuSeries out = applyErrors(in, m, 1);
  const Vector3d centripetal = kOmega.cross(kOmega.cross(m.lever_arm.r_m));
  for (size_t k = 0; k < in.size(); ++k) {
    EXPECT_LT((out[k].dvel_m_s / dt - (kF + centripetal)).norm(), 1e-11) << k;
    EXPECT_EQ(out[k].dtheta_rad, in[k].dtheta_rad);
  }
}

TEST(ImuErrorModel, LeverArmOnAngularAccelerationAddsTangentialForce) {
  // omega(t) = w0 + alpha (t - t0): the mean extra specific force over [a, b] is
  // alpha x r + mean of omega x (omega x r), which Simpson's rule integrates exactly (quartic).
  const Vector3d w0(0.1, 0.2, -0.3), alpha(0.5, -0.2, 0.8);
  const Vector3d r(1.2, 0.3, -0.5);
  // Start at t = 0: the interval lengths b - a of the synthetic data then carry no rounding of
  // large time tags (which the differentiated rates would amplify).
  const double t_start = 0.0;
  auto omega = [&](double t) { return Vector3d(w0 + alpha * (t - t_start)); };
  const IntervalFn gyro = [&](double a, double b) {
    return Vector3d((w0 + alpha * (0.5 * (a + b) - t_start)) * (b - a));
  };
  const double dt = 0.01;
  const ImuSeries in = makeSeries(300, dt, gyro, constantRate(kF), t_start);
  ImuErrorModel m;
  m.lever_arm.r_m = r;
  const ImuSeries out = applyErrors(in, m, 1);
  auto cp = [&](double t) {
    const Vector3d w = omega(t);
    return Vector3d(w.cross(w.cross(r)));
  };
  for (size_t k = 0; k < in.size(); ++k) {
    const double b = in[k].t_s, a = b - dt;
    // Mean of the (quadratic in t) centripetal term by Boole's rule, exact to degree 5.
    const double h = dt / 4.0;
    const Vector3d mean_cp = (7.0 * cp(a) + 32.0 * cp(a + h) + 12.0 * cp(a + 2 * h) +
                              32.0 * cp(a + 3 * h) + 7.0 * cp(b)) /
                             90.0;
    const Vector3d expected = kF + alpha.cross(r) + mean_cp;
    EXPECT_LT((out[k].dvel_m_s / dt - expected).norm(), 1e-10) << k;
  }
}

TEST(ImuErrorModel, MountingMisalignmentRotatesBothTriads) {
  ImuErrorModel m;
  m.mounting_misalignment.rotation_rad = Vector3d(2e-3, -1e-3, 5e-3);
  const double dt = 0.01;
  const ImuSeries out = applyErrors(constantSeries(10, dt, kOmega, kF), m, 1);
  // C_bt = exp(rotation) (rotation of t relative to b), so C_tb = exp(rotation)^T.
  const Matrix3d C_tb = dcmFromRotationVector(m.mounting_misalignment.rotation_rad).transpose();
  // First order: C_tb = I - skew(rotation), i.e. omega_t = omega - rotation x omega.
  EXPECT_LT((C_tb - (Matrix3d::Identity() - skew(m.mounting_misalignment.rotation_rad))).norm(),
            3e-5);
  for (const auto& s : out) {
    EXPECT_LT((s.dtheta_rad / dt - C_tb * kOmega).norm(), 1e-14);
    EXPECT_LT((s.dvel_m_s / dt - C_tb * kF).norm(), 1e-12);
    // Rotation preserves norms.
    EXPECT_NEAR(s.dvel_m_s.norm() / dt, kF.norm(), 1e-12);
  }
  // Sign convention: a +z rotation of t relative to b turns the tested x axis toward reference
  // +y, so a pure reference +y rate appears (as sin(angle)) on the tested +x axis.
  ImuErrorModel yaw;
  yaw.mounting_misalignment.rotation_rad = Vector3d(0, 0, 0.01);
  const ImuSeries o2 = applyErrors(constantSeries(2, dt, Vector3d(0, 1, 0), kF), yaw, 1);
  EXPECT_NEAR(o2[0].dtheta_rad.x() / dt, std::sin(0.01), 1e-14);
}

TEST(ImuErrorModel, LeverArmIsResolvedInTheReferenceFrameBeforeMisalignment) {
  ImuErrorModel m;
  m.lever_arm.r_m = Vector3d(0.5, 0.1, -0.2);
  m.mounting_misalignment.rotation_rad = Vector3d(0.01, 0.02, -0.03);
  const double dt = 0.01;
  const ImuSeries out = applyErrors(constantSeries(20, dt, kOmega, kF), m, 1);
  const Matrix3d C_tb = dcmFromRotationVector(m.mounting_misalignment.rotation_rad).transpose();
  const Vector3d expected = C_tb * (kF + kOmega.cross(kOmega.cross(m.lever_arm.r_m)));
  for (const auto& s : out) EXPECT_LT((s.dvel_m_s / dt - expected).norm(), 1e-11);
}

TEST(ImuErrorModel, GeometryRejectsNonContiguousSamples) {
  ImuSeries in = constantSeries(10, 0.01, kOmega, kF);
  in[5].t_s += 0.02;  // gap
  for (int i = 5; i < 10; ++i) in[i].t_s += 0.02;
  ImuErrorModel m;
  m.time_offset.tau_s = 0.001;
  EXPECT_THROW(applyErrors(in, m, 1), std::invalid_argument);
  m.time_offset.tau_s = 0.0;
  m.mounting_misalignment.rotation_rad = Vector3d(0, 0, 0.01);
  EXPECT_NO_THROW(applyErrors(in, m, 1));  // pure rotation needs no neighbours
}

}  // namespace
}  // namespace graftnav
