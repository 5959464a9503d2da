// Each IMU error term against its analytic effect; the stochastic terms against their
// sampling distributions (seeded, tolerances from the estimator's standard error).
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

namespace graftnav {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using IntervalFn = std::function<Vector3d(double, double)>;  // integral over [t0, t1]

constexpr double kPi = 3.14159265358979323846;

// Samples k = 0..n-1 covering [t_start + k dt, t_start + (k+1) dt], increments from exact
// integrals.
ImuSeries makeSeries(int n, double dt, const IntervalFn& dtheta, const IntervalFn& dvel,
                     double t_start = 1000.0) {
  ImuSeries s(n);
  for (int k = 0; k < n; ++k) {
    const double t0 = t_start + k * dt;
    const double t1 = t_start + (k + 1) * dt;
    s[k].t_s = t1;
    s[k].dt_s = dt;
    s[k].dtheta_rad = dtheta(t0, t1);
    s[k].dvel_m_s = dvel(t0, t1);
  }
  return s;
}

IntervalFn constantRate(const Vector3d& x) {
  return [x](double t0, double t1) { return Vector3d(x * (t1 - t0)); };
}

// Constant inputs with increments exactly x * dt (no rounding of time differences).
ImuSeries constantSeries(int n, double dt, const Vector3d& omega, const Vector3d& f) {
  ImuSeries s(n);
  for (int k = 0; k < n; ++k) {
    s[k].t_s = 1000.0 + (k + 1) * dt;
    s[k].dt_s = dt;
    s[k].dtheta_rad = omega * dt;
    s[k].dvel_m_s = f * dt;
  }
  return s;
}

const Vector3d kOmega(0.12, -0.31, 0.47);  // rad/s
const Vector3d kF(0.8, -1.3, -9.79);       // m/s^2

// ---- deterministic terms ----------------------------------------------------------------

TEST(ImuErrorModel, IdealModelLeavesIncrementsBitIdentical) {
  ImuSeries in = makeSeries(
      500, 0.005,
      [](double a, double b) { return Vector3d(std::sin(a) - std::sin(b), a * b, 0.1 * (b - a)); },
      [](double a, double b) { return Vector3d(b * b - a * a, -0.3, std::cos(a) - std::cos(b)); });
  for (auto& s : in) s.temperature_degC = 31.5;
  const ImuErrorModel m;
  EXPECT_TRUE(m.isIdeal());
  EXPECT_TRUE(m.describe().empty());
  const ImuSeries out = applyErrors(in, m, 7);
  ASSERT_EQ(out.size(), in.size());
  for (size_t k = 0; k < in.size(); ++k) {
    EXPECT_EQ(out[k].t_s, in[k].t_s);
    EXPECT_EQ(out[k].dt_s, in[k].dt_s);
    EXPECT_EQ(out[k].dtheta_rad, in[k].dtheta_rad);
    EXPECT_EQ(out[k].dvel_m_s, in[k].dvel_m_s);
    EXPECT_EQ(out[k].temperature_degC, in[k].temperature_degC);
  }
}

TEST(ImuErrorModel, ConstantBiasAddsBiasTimesDt) {
  ImuErrorModel m;
  m.gyro.constant_bias.b = Vector3d(1e-4, -2e-4, 3e-5);
  m.accel.constant_bias.b = Vector3d(0.01, 0.02, -0.03);
  for (double dt : {0.01, 0.005}) {
    const ImuSeries in = constantSeries(100, dt, kOmega, kF);
    const ImuSeries out = applyErrors(in, m, 1);
    for (size_t k = 0; k < in.size(); ++k) {
      EXPECT_LT((out[k].dtheta_rad - in[k].dtheta_rad - m.gyro.constant_bias.b * dt).norm(), 1e-17);
      EXPECT_LT((out[k].dvel_m_s - in[k].dvel_m_s - m.accel.constant_bias.b * dt).norm(), 1e-15);
    }
  }
}

TEST(ImuErrorModel, ScaleFactorAndNonOrthogonalityGiveMTimesRate) {
  ImuErrorModel m;
  m.gyro.scale_factor.k = Vector3d(300e-6, -150e-6, 1000e-6);
  m.gyro.non_orthogonality.N << 0, 1e-3, -2e-3, 5e-4, 0, 3e-4, -7e-4, 2e-4, 0;
  m.accel.scale_factor.k = Vector3d(-1e-3, 2e-3, 5e-4);
  m.accel.non_orthogonality.N << 0, -4e-4, 1e-3, 2e-3, 0, -6e-4, 3e-4, 9e-4, 0;
  // M = I + S + N of seed Eq. 1-2, written out element by element.
  Matrix3d Mg = Matrix3d::Identity();
  Matrix3d Ma = Matrix3d::Identity();
  for (int i = 0; i < 3; ++i) {
    Mg(i, i) += m.gyro.scale_factor.k[i];
    Ma(i, i) += m.accel.scale_factor.k[i];
    for (int j = 0; j < 3; ++j) {
      if (i != j) {
        Mg(i, j) = m.gyro.non_orthogonality.N(i, j);
        Ma(i, j) = m.accel.non_orthogonality.N(i, j);
      }
    }
  }
  EXPECT_LT((m.gyro.scaleMisalignmentMatrix() - Mg).norm(), 1e-15);
  const double dt = 0.01;
  const ImuSeries out = applyErrors(constantSeries(50, dt, kOmega, kF), m, 1);
  for (const auto& s : out) {
    EXPECT_LT((s.dtheta_rad / dt - Mg * kOmega).norm(), 1e-13);
    EXPECT_LT((s.dvel_m_s / dt - Ma * kF).norm(), 1e-12);
  }
  EXPECT_LT((m.gyroDeterministic(kOmega, kF) - Mg * kOmega).norm(), 1e-15);
  EXPECT_LT((m.accelDeterministic(kF) - Ma * kF).norm(), 1e-14);
}

TEST(ImuErrorModel, GSensitivityGivesBiasGTimesSpecificForce) {
  ImuErrorModel m;
  m.g_sensitivity.G << 1e-5, -2e-5, 3e-5, 4e-6, 5e-5, -6e-6, 7e-6, 8e-6, -9e-5;
  const double dt = 0.005;
  for (const Vector3d& f : {kF, Vector3d(0, 0, -9.8), Vector3d(3.0, -2.0, -9.0)}) {
    const ImuSeries in = constantSeries(20, dt, kOmega, f);
    const ImuSeries out = applyErrors(in, m, 1);
    for (size_t k = 0; k < in.size(); ++k) {
      // Element-wise G f, independent of Eigen's product.
      Vector3d Gf;
      for (int i = 0; i < 3; ++i) {
        Gf[i] = m.g_sensitivity.G(i, 0) * f[0] + m.g_sensitivity.G(i, 1) * f[1] +
                m.g_sensitivity.G(i, 2) * f[2];
      }
      EXPECT_LT(((out[k].dtheta_rad - in[k].dtheta_rad) / dt - Gf).norm(), 1e-15);
      EXPECT_EQ(out[k].dvel_m_s, in[k].dvel_m_s);  // the accelerometer is untouched
    }
  }
}

TEST(ImuErrorModel, ScaleAsymmetryDependsOnSignOfTrueInput) {
  ImuErrorModel m;
  m.gyro.scale_asymmetry.k_pos = Vector3d(1e-3, 2e-3, 3e-3);
  m.gyro.scale_asymmetry.k_neg = Vector3d(-4e-3, 5e-3, -6e-3);
  m.accel.scale_asymmetry.k_pos = Vector3d(7e-4, 0, 0);
  m.accel.scale_asymmetry.k_neg = Vector3d(-8e-4, 0, 0);
  const double dt = 0.01;
  const Vector3d w(0.5, -0.5, 0.25);
  for (double sign : {1.0, -1.0}) {
    const Vector3d omega = sign * w;
    const Vector3d f(sign * 2.0, 1.0, -9.8);
    const ImuSeries out = applyErrors(constantSeries(5, dt, omega, f), m, 1);
    Vector3d expect_g, expect_a = f;
    for (int i = 0; i < 3; ++i) {
      const double k =
          omega[i] > 0 ? m.gyro.scale_asymmetry.k_pos[i] : m.gyro.scale_asymmetry.k_neg[i];
      expect_g[i] = (1.0 + k) * omega[i];
    }
    expect_a[0] = (1.0 + (sign > 0 ? 7e-4 : -8e-4)) * f[0];
    for (const auto& s : out) {
      EXPECT_LT((s.dtheta_rad / dt - expect_g).norm(), 1e-14) << "sign " << sign;
      EXPECT_LT((s.dvel_m_s / dt - expect_a).norm(), 1e-13) << "sign " << sign;
    }
  }
}

TEST(ImuErrorModel, QuadraticNonlinearityOnConstantRate) {
  ImuErrorModel m;
  m.gyro.scale_nonlinearity.k2 = Vector3d(1e-3, -2e-3, 5e-4);   // 1/(rad/s)
  m.accel.scale_nonlinearity.k2 = Vector3d(1e-4, 2e-4, -3e-4);  // 1/(m/s^2)
  const double dt = 0.005;
  const ImuSeries out = applyErrors(constantSeries(5, dt, kOmega, kF), m, 1);
  for (const auto& s : out) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s.dtheta_rad[i] / dt,
                  kOmega[i] + m.gyro.scale_nonlinearity.k2[i] * kOmega[i] * kOmega[i], 1e-14);
      EXPECT_NEAR(s.dvel_m_s[i] / dt, kF[i] + m.accel.scale_nonlinearity.k2[i] * kF[i] * kF[i],
                  1e-12);
    }
  }
}

TEST(ImuErrorModel, TemperatureRampGivesLinearBiasAndScale) {
  ImuErrorModel m;
  m.gyro.temperature_bias.per_degC = Vector3d(1e-6, -2e-6, 3e-6);  // rad/s/degC
  m.gyro.temperature_bias.t_ref_degC = 20.0;
  m.gyro.temperature_scale.per_degC = Vector3d(1e-5, 0, -2e-5);     // 1/degC
  m.accel.temperature_bias.per_degC = Vector3d(1e-4, 2e-4, -5e-4);  // m/s^2/degC
  m.accel.temperature_bias.t_ref_degC = 25.0;
  const double dt = 0.01;
  ImuSeries in = constantSeries(3000, dt, kOmega, kF);
  for (size_t k = 0; k < in.size(); ++k)
    in[k].temperature_degC = 10.0 + 30.0 * k / (in.size() - 1.0);
  const ImuSeries out = applyErrors(in, m, 1);
  for (size_t k = 0; k < in.size(); k += 97) {
    const double T = in[k].temperature_degC;
    for (int i = 0; i < 3; ++i) {
      const double eg = m.gyro.temperature_bias.per_degC[i] * (T - 20.0) +
                        m.gyro.temperature_scale.per_degC[i] * (T - 20.0) * kOmega[i];
      const double ea = m.accel.temperature_bias.per_degC[i] * (T - 25.0);
      EXPECT_NEAR((out[k].dtheta_rad[i] - in[k].dtheta_rad[i]) / dt, eg, 1e-15);
      EXPECT_NEAR((out[k].dvel_m_s[i] - in[k].dvel_m_s[i]) / dt, ea, 1e-13);
    }
  }
  // A temperature term without a temperature column is an error, not a silent zero.
  EXPECT_THROW(applyErrors(constantSeries(3, dt, kOmega, kF), m, 1), std::invalid_argument);
  EXPECT_THROW(m.gyroDeterministic(kOmega, kF), std::invalid_argument);
}

TEST(ImuErrorModel, VibrationRectificationOfASinusoidalVibration) {
  // Vibration A sin(2 pi fv t) on the x accelerometer over gravity. Mean input per interval has
  // amplitude A' = A sinc(pi fv dt); the discrete high-pass of VibrationRegressor has gain
  // |HP(e^{j th})|^2 = (1-a)^2 |1 - e^{-j th}|^2 / |1 - (1-a) e^{-j th}|^2, th = 2 pi fv dt, so
  // the regressor settles at A'^2 |HP|^2 / 2 and the bias at coeff times that.
  const double A = 2.0, fv = 17.0, dt = 0.005, window = 0.5;
  const double w = 2.0 * kPi * fv;
  ImuErrorModel m;
  m.accel.vibration_rectification.coeff = Vector3d(2e-4, -1e-4, 5e-4);  // m/s^2 per (m/s^2)^2
  m.accel.vibration_rectification.regressor = "specific_force_hp_sq";
  m.accel.vibration_rectification.window_s = window;
  m.gyro.vibration_rectification.coeff = Vector3d(0, 0, 1e-5);  // rad/s per (m/s^2)^2
  m.gyro.vibration_rectification.window_s = window;
  const IntervalFn dvel = [&](double t0, double t1) {
    return Vector3d((std::cos(w * t0) - std::cos(w * t1)) * A / w, 0.0, -9.8 * (t1 - t0));
  };
  const ImuSeries in =
      makeSeries(static_cast<int>(30.0 / dt), dt, constantRate(Vector3d::Zero()), dvel, 0.0);
  const ImuSeries out = applyErrors(in, m, 1);
  const double a = -std::expm1(-dt / window);
  const double th = w * dt;
  const std::complex<double> z1 = std::exp(std::complex<double>(0, -th));
  const double hp2 = std::norm((1.0 - a) * (1.0 - z1) / (1.0 - (1.0 - a) * z1));
  const double amp = A * std::sin(0.5 * th) / (0.5 * th);
  const double r_expected = 0.5 * amp * amp * hp2;
  // Average the bias over the last 10 s (steady state after 40 window lengths).
  Vector3d mean_a = Vector3d::Zero();
  double mean_g = 0.0;
  int count = 0;
  for (size_t k = in.size() - static_cast<size_t>(10.0 / dt); k < in.size(); ++k) {
    mean_a += (out[k].dvel_m_s - in[k].dvel_m_s) / dt;
    mean_g += (out[k].dtheta_rad.z() - in[k].dtheta_rad.z()) / dt;
    ++count;
  }
  mean_a /= count;
  mean_g /= count;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean_a[i], m.accel.vibration_rectification.coeff[i] * r_expected,
                1e-3 * std::abs(m.accel.vibration_rectification.coeff[i] * r_expected));
  }
  EXPECT_NEAR(mean_g, 1e-5 * r_expected, 1e-3 * 1e-5 * r_expected);
  // No vibration, no rectified bias (constant specific force has no high-pass content).
  const ImuSeries quiet = applyErrors(constantSeries(2000, dt, kOmega, kF), m, 1);
  for (const auto& s : quiet) EXPECT_LT((s.dvel_m_s / dt - kF).norm(), 1e-12);
}

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

// ---- quantization -----------------------------------------------------------------------

TEST(ImuErrorModel, QuantizationKeepsCumulativeSumWithinHalfAStep) {
  ImuErrorModel m;
  m.gyro.quantization.step = Vector3d(1e-6, 2e-6, 5e-7);
  m.accel.quantization.step = Vector3d(1e-4, 1e-4, 3e-4);
  StandardNormalSampler rng(99);
  const double dt = 0.005;
  ImuSeries in(20000);
  for (size_t k = 0; k < in.size(); ++k) {
    in[k].t_s = (k + 1) * dt;
    in[k].dt_s = dt;
    in[k].dtheta_rad = 1e-4 * rng.next3();
    in[k].dvel_m_s = Vector3d(0, 0, -9.8 * dt) + 1e-2 * rng.next3();
  }
  const ImuSeries out = applyErrors(in, m, 1);
  Vector3d sum_in_g = Vector3d::Zero(), sum_out_g = Vector3d::Zero();
  Vector3d sum_in_a = Vector3d::Zero(), sum_out_a = Vector3d::Zero();
  double worst = 0.0;
  for (size_t k = 0; k < in.size(); ++k) {
    sum_in_g += in[k].dtheta_rad;
    sum_out_g += out[k].dtheta_rad;
    sum_in_a += in[k].dvel_m_s;
    sum_out_a += out[k].dvel_m_s;
    for (int i = 0; i < 3; ++i) {
      const double cg = out[k].dtheta_rad[i] / m.gyro.quantization.step[i];
      const double ca = out[k].dvel_m_s[i] / m.accel.quantization.step[i];
      ASSERT_NEAR(cg, std::round(cg), 1e-6);  // whole counts
      ASSERT_NEAR(ca, std::round(ca), 1e-6);
      const double eg = std::abs(sum_out_g[i] - sum_in_g[i]) / m.gyro.quantization.step[i];
      const double ea = std::abs(sum_out_a[i] - sum_in_a[i]) / m.accel.quantization.step[i];
      worst = std::max({worst, eg, ea});
      ASSERT_LE(eg, 0.5 + 1e-6) << k;
      ASSERT_LE(ea, 0.5 + 1e-6) << k;
    }
  }
  // Without the carried remainder the error would random-walk to ~ sqrt(N/12) ~ 40 steps.
  EXPECT_GT(worst, 0.3);
}

// ---- stochastic terms -------------------------------------------------------------------

class GaussMarkovAtRate : public ::testing::TestWithParam<double> {};

// Sample autocorrelation at lag m, pooled over the three axes of a (n x 3) set of series.
double sampleAutocorr(const std::vector<Vector3d>& x, int lag) {
  double num = 0.0, den = 0.0;
  for (int i = 0; i < 3; ++i) {
    double mean = 0.0;
    for (const auto& v : x) mean += v[i];
    mean /= x.size();
    for (size_t k = 0; k < x.size(); ++k) {
      const double d = x[k][i] - mean;
      den += d * d;
      if (k + lag < x.size()) num += d * (x[k + lag][i] - mean);
    }
  }
  return num / den;
}

TEST_P(GaussMarkovAtRate, StationaryVarianceAndCorrelationMatchExactDiscretization) {
  const double rate_hz = GetParam();
  const double dt = 1.0 / rate_hz;
  // tau comparable to dt so that an approximate (Euler) discretization would be caught: at
  // 100 Hz, q = 2 sigma^2 dt / tau would inflate the stationary variance by 21 %.
  const double tau = 0.05;
  const Vector3d sigma(1e-4, 2e-4, 5e-5);  // rad/s
  ImuErrorModel m;
  m.gyro.bias_instability.sigma = sigma;
  m.gyro.bias_instability.tau_s = tau;
  const int n = 200000;
  const ImuSeries out = applyErrors(constantSeries(n, dt, Vector3d::Zero(), kF), m, 2024);
  std::vector<Vector3d> b(n);
  for (int k = 0; k < n; ++k) b[k] = (out[k].dtheta_rad / dt).cwiseQuotient(sigma);  // N(0,1)
  const double rho = std::exp(-dt / tau);
  // Variance of the (unit) process, pooled over 3 axes: standard error of s^2 for AR(1),
  // sqrt(2 (1 + rho^2) / (N (1 - rho^2))).
  double var = 0.0;
  for (const auto& v : b) var += v.squaredNorm();
  var /= 3.0 * n;
  const double se_var = std::sqrt(2.0 * (1 + rho * rho) / (3.0 * n * (1 - rho * rho)));
  EXPECT_NEAR(var, 1.0, 5.0 * se_var);
  // Bartlett's formula for the standard error of the lag-m autocorrelation of an AR(1).
  auto se_corr = [&](int lag) {
    const double r2m = std::pow(rho, 2 * lag);
    return std::sqrt(((1 + rho * rho) * (1 - r2m) / (1 - rho * rho) - 2.0 * lag * r2m) / (3.0 * n));
  };
  EXPECT_NEAR(sampleAutocorr(b, 1), rho, 5.0 * se_corr(1));
  const int lag_tau = static_cast<int>(std::lround(tau / dt));
  EXPECT_NEAR(sampleAutocorr(b, lag_tau), std::exp(-1.0), 5.0 * se_corr(lag_tau));
  // The one-step coefficients themselves.
  EXPECT_DOUBLE_EQ(GaussMarkov::transition(dt, tau), rho);
  EXPECT_NEAR(GaussMarkov::drivingNoiseStd(2.0, dt, tau), 2.0 * std::sqrt(1 - rho * rho), 1e-15);
}

INSTANTIATE_TEST_SUITE_P(Rates, GaussMarkovAtRate, ::testing::Values(100.0, 200.0));

TEST(GaussMarkov, StationaryStartAndZeroStart) {
  GaussMarkovParams p;
  p.sigma = Vector3d(1.0, 2.0, 3.0);
  p.tau_s = 100.0;
  // Ensemble of first samples: variance sigma^2 when stationary, exactly zero otherwise.
  StandardNormalSampler rng(5);
  Vector3d var = Vector3d::Zero();
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    GaussMarkov gm(p);
    gm.initialize(rng);
    var += gm.state().cwiseAbs2();
  }
  var /= n;
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(var[i] / (p.sigma[i] * p.sigma[i]), 1.0, 5.0 * std::sqrt(2.0 / n));
  p.start_stationary = false;
  GaussMarkov gm0(p);
  gm0.initialize(rng);
  EXPECT_EQ(gm0.state(), Vector3d::Zero());
  // tau = inf: a random constant.
  p.tau_s = std::numeric_limits<double>::infinity();
  p.start_stationary = true;
  GaussMarkov gmc(p);
  gmc.initialize(rng);
  const Vector3d x0 = gmc.state();
  gmc.propagate(10.0, rng);
  EXPECT_EQ(gmc.state(), x0);
  EXPECT_THROW(GaussMarkov(GaussMarkovParams{Vector3d::Ones(), -1.0, true}), std::invalid_argument);
}

class WhiteNoiseAtRate : public ::testing::TestWithParam<double> {};

TEST_P(WhiteNoiseAtRate, IncrementStdIsDensityTimesSqrtDt) {
  const double dt = 1.0 / GetParam();
  ImuErrorModel m;
  m.gyro.white_noise.density = Vector3d(1e-4, 2e-4, 4e-4);   // ARW rad/sqrt(s)
  m.accel.white_noise.density = Vector3d(1e-3, 5e-4, 2e-3);  // VRW m/s/sqrt(s)
  const int n = 100000;
  const ImuSeries in = constantSeries(n, dt, kOmega, kF);
  const ImuSeries out = applyErrors(in, m, 11);
  Vector3d sg = Vector3d::Zero(), sa = Vector3d::Zero(), mg = Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    const Vector3d eg = out[k].dtheta_rad - in[k].dtheta_rad;
    const Vector3d ea = out[k].dvel_m_s - in[k].dvel_m_s;
    sg += eg.cwiseAbs2();
    sa += ea.cwiseAbs2();
    mg += eg;
  }
  const double se_std = 1.0 / std::sqrt(2.0 * n);  // relative standard error of a sample std
  for (int i = 0; i < 3; ++i) {
    const double std_g = std::sqrt(sg[i] / n), std_a = std::sqrt(sa[i] / n);
    EXPECT_NEAR(std_g / (m.gyro.white_noise.density[i] * std::sqrt(dt)), 1.0, 5.0 * se_std);
    EXPECT_NEAR(std_a / (m.accel.white_noise.density[i] * std::sqrt(dt)), 1.0, 5.0 * se_std);
    EXPECT_NEAR(mg[i] / n, 0.0, 5.0 * m.gyro.white_noise.density[i] * std::sqrt(dt / n));
  }
}

INSTANTIATE_TEST_SUITE_P(Rates, WhiteNoiseAtRate, ::testing::Values(100.0, 200.0));

TEST(ImuErrorModel, MeanRateOfArwNoiseOverTHasStdArwOverSqrtT) {
  // Seed Eq. 12: D = sigma_RW / sqrt(t_static), checked on 1 s and 4 s averages at 200 Hz.
  const double dt = 0.005, arw = 3e-4;
  ImuErrorModel m;
  m.gyro.white_noise.density.setConstant(arw);
  const int n = 800000;
  const ImuSeries out = applyErrors(constantSeries(n, dt, Vector3d::Zero(), kF), m, 3);
  for (double T : {1.0, 4.0}) {
    const int per = static_cast<int>(std::lround(T / dt));
    const int windows = n / per;
    double ss = 0.0;
    for (int w = 0; w < windows; ++w) {
      Vector3d sum = Vector3d::Zero();
      for (int k = w * per; k < (w + 1) * per; ++k) sum += out[k].dtheta_rad;
      ss += (sum / T).squaredNorm();
    }
    const int count = 3 * windows;
    const double std_mean = std::sqrt(ss / count);
    EXPECT_NEAR(std_mean / (arw / std::sqrt(T)), 1.0, 5.0 * std::sqrt(0.5 / count)) << "T " << T;
  }
}

TEST(ImuErrorModel, BiasRandomWalkStepsHaveStdDensityTimesSqrtDt) {
  const double dt = 0.01;
  ImuErrorModel m;
  m.accel.bias_random_walk.density = Vector3d(1e-4, 3e-4, 2e-5);  // m/s^2/sqrt(s)
  const int n = 50000;
  const ImuSeries in = constantSeries(n, dt, kOmega, kF);
  const ImuSeries out = applyErrors(in, m, 8);
  Vector3d prev = (out[0].dvel_m_s - in[0].dvel_m_s) / dt;
  EXPECT_LT(prev.norm(), 1e-12);  // b_0 = 0
  Vector3d ss = Vector3d::Zero();
  for (int k = 1; k < n; ++k) {
    const Vector3d b = (out[k].dvel_m_s - in[k].dvel_m_s) / dt;
    ss += (b - prev).cwiseAbs2();
    prev = b;
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::sqrt(ss[i] / (n - 1)) / (m.accel.bias_random_walk.density[i] * std::sqrt(dt)),
                1.0, 5.0 * std::sqrt(0.5 / n));
  }
}

// ---- determinism and composition --------------------------------------------------------

ImuErrorModel noisyModel() {
  ImuErrorModel m;
  m.gyro.white_noise.density.setConstant(1e-4);
  m.gyro.bias_instability.sigma.setConstant(1e-5);
  m.gyro.bias_instability.tau_s = 100.0;
  m.accel.white_noise.density.setConstant(1e-3);
  m.accel.bias_random_walk.density.setConstant(1e-5);
  return m;
}

TEST(ImuErrorModel, SameSeedSameOutputDifferentSeedDifferentOutput) {
  const ImuSeries in = constantSeries(1000, 0.005, kOmega, kF);
  const ImuErrorModel m = noisyModel();
  const ImuSeries a = applyErrors(in, m, 42);
  const ImuSeries b = applyErrors(in, m, 42);
  const ImuSeries c = applyErrors(in, m, 43);
  int differ = 0;
  for (size_t k = 0; k < in.size(); ++k) {
    ASSERT_EQ(a[k].dtheta_rad, b[k].dtheta_rad);
    ASSERT_EQ(a[k].dvel_m_s, b[k].dvel_m_s);
    if (a[k].dtheta_rad != c[k].dtheta_rad && a[k].dvel_m_s != c[k].dvel_m_s) ++differ;
  }
  EXPECT_EQ(differ, static_cast<int>(in.size()));
  // The generator used sample by sample is the same as the whole-series function.
  ImuErrorGenerator gen(m, 42);
  for (size_t k = 0; k < in.size(); ++k) ASSERT_EQ(gen.apply(in[k]).dtheta_rad, a[k].dtheta_rad);
}

TEST(ImuErrorModel, VibrationRegressorRestartsAtEachRecordNoiseStreamRunsOn) {
  // Two static lab records, gravity on z then on x. Concatenated, the pose change is a 9.8 m/s^2
  // step into the high-pass: a rectified bias of ~coeff g^2 in the second record's first seconds
  // that no vibration caused. As separate records, a static pose has no rectified bias at all.
  const double dt = 0.005;
  ImuErrorModel m;
  m.accel.vibration_rectification.coeff = Vector3d(1e-2, -8e-3, 5e-3);
  const ImuSeries z_up = constantSeries(2000, dt, Vector3d::Zero(), Vector3d(0, 0, 9.8));
  const ImuSeries x_up = constantSeries(2000, dt, Vector3d::Zero(), Vector3d(9.8, 0, 0));
  ImuSeries joined = z_up;
  joined.insert(joined.end(), x_up.begin(), x_up.end());
  const ImuSeries concatenated = applyErrors(joined, m, 3);
  double transient = 0.0;
  for (size_t k = z_up.size(); k < joined.size(); ++k)
    transient = std::max(transient, (concatenated[k].dvel_m_s - joined[k].dvel_m_s).norm() / dt);
  EXPECT_GT(transient, 0.1);  // what the simulator's lab files carried before records
  const std::vector<ImuSeries> records = applyErrorsToRecords({z_up, x_up}, m, 3);
  ASSERT_EQ(records.size(), 2u);
  for (int r = 0; r < 2; ++r) {
    const ImuSeries& in = r == 0 ? z_up : x_up;
    ASSERT_EQ(records[r].size(), in.size());
    for (size_t k = 0; k < in.size(); ++k)
      EXPECT_LT((records[r][k].dvel_m_s - in[k].dvel_m_s).norm() / dt, 1e-12);
  }
  // Noise, bias processes and quantization run on through the records exactly as through the
  // concatenation (CRN cases share the lab's first record with the field noise stream).
  ImuErrorModel noisy = noisyModel();
  noisy.accel.quantization.step.setConstant(2e-5);
  const ImuSeries whole = applyErrors(joined, noisy, 11);
  const std::vector<ImuSeries> parts = applyErrorsToRecords({z_up, x_up}, noisy, 11);
  for (size_t k = 0; k < joined.size(); ++k) {
    const ImuSample& p = k < z_up.size() ? parts[0][k] : parts[1][k - z_up.size()];
    ASSERT_EQ(p.dtheta_rad, whole[k].dtheta_rad);
    ASSERT_EQ(p.dvel_m_s, whole[k].dvel_m_s);
  }
}

TEST(ImuErrorModel, SwitchingOneTermLeavesTheOtherRealizationsUnchanged) {
  const ImuSeries in = constantSeries(500, 0.01, kOmega, kF);
  ImuErrorModel only_gyro;
  only_gyro.gyro.white_noise.density.setConstant(1e-4);
  ImuErrorModel both = only_gyro;
  both.accel.white_noise.density.setConstant(1e-3);
  both.gyro.bias_random_walk.density.setConstant(1e-6);
  ImuErrorModel only_accel;
  only_accel.accel.white_noise.density.setConstant(1e-3);
  ImuErrorModel only_rw;
  only_rw.gyro.bias_random_walk.density.setConstant(1e-6);
  const ImuSeries a = applyErrors(in, only_gyro, 5);
  const ImuSeries b = applyErrors(in, both, 5);
  const ImuSeries c = applyErrors(in, only_accel, 5);
  const ImuSeries d = applyErrors(in, only_rw, 5);
  double rw_size = 0.0;
  for (size_t k = 0; k < in.size(); ++k) {
    // Gyro in `both` = in + white (as in only_gyro) + random-walk bias (as in only_rw).
    const Vector3d expected = a[k].dtheta_rad + (d[k].dtheta_rad - in[k].dtheta_rad);
    EXPECT_LT((b[k].dtheta_rad - expected).norm(), 1e-17);
    rw_size = std::max(rw_size, (d[k].dtheta_rad - in[k].dtheta_rad).norm());
    ASSERT_EQ(b[k].dvel_m_s, c[k].dvel_m_s);
  }
  EXPECT_GT(rw_size, 1e-10);  // the random walk is really there
}

TEST(ImuErrorModel, CombinedDeterministicTermsEqualTheDeterministicFunction) {
  ImuErrorModel m;
  m.gyro.constant_bias.b = Vector3d(1e-4, 2e-4, -1e-4);
  m.gyro.scale_factor.k = Vector3d(1e-3, -2e-3, 5e-4);
  m.gyro.non_orthogonality.N << 0, 1e-3, 0, -1e-3, 0, 2e-3, 0, 0, 0;
  m.gyro.scale_asymmetry.k_neg = Vector3d(1e-3, 1e-3, 1e-3);
  m.gyro.scale_nonlinearity.k2 = Vector3d(1e-3, 0, 0);
  m.gyro.temperature_bias.per_degC = Vector3d(1e-6, 1e-6, 1e-6);
  m.g_sensitivity.G = 1e-5 * Matrix3d::Ones();
  m.accel.constant_bias.b = Vector3d(0.01, 0, 0);
  m.accel.scale_factor.k = Vector3d(1e-3, 1e-3, -1e-3);
  m.accel.temperature_scale.per_degC = Vector3d(1e-5, 0, 0);
  const double dt = 0.01, T = 37.0;
  ImuSeries in = constantSeries(10, dt, kOmega, kF);
  for (auto& s : in) s.temperature_degC = T;
  const ImuSeries out = applyErrors(in, m, 1);
  // Sum of the individual analytic effects (each acting on the true input).
  Vector3d eg = m.gyro.constant_bias.b + m.gyro.scale_factor.k.cwiseProduct(kOmega) +
                m.gyro.non_orthogonality.N * kOmega + m.g_sensitivity.G * kF +
                Vector3d(0, 1e-3 * kOmega.y(), 0) + Vector3d(1e-3 * kOmega.x() * kOmega.x(), 0, 0) +
                m.gyro.temperature_bias.per_degC * (T - m.gyro.temperature_bias.t_ref_degC);
  Vector3d ea = m.accel.constant_bias.b + m.accel.scale_factor.k.cwiseProduct(kF) +
                Vector3d(1e-5 * (T - 25.0) * kF.x(), 0, 0);
  for (const auto& s : out) {
    EXPECT_LT((s.dtheta_rad / dt - (kOmega + eg)).norm(), 1e-14);
    EXPECT_LT((s.dvel_m_s / dt - (kF + ea)).norm(), 1e-12);
    EXPECT_LT((s.dtheta_rad / dt - m.gyroDeterministic(kOmega, kF, T)).norm(), 1e-14);
    EXPECT_LT((s.dvel_m_s / dt - m.accelDeterministic(kF, T)).norm(), 1e-12);
  }
}

TEST(ImuErrorModel, DescribeListsActiveTermsInOrder) {
  ImuErrorModel m = noisyModel();
  m.lever_arm.r_m = Vector3d(0.1, 0, 0);
  m.time_offset.tau_s = 0.002;
  m.g_sensitivity.G(0, 2) = 1e-5;
  m.accel.quantization.step.setConstant(1e-4);
  std::vector<std::string> names;
  for (const auto& d : m.describe()) {
    names.push_back(d.sensor + ":" + d.name);
    EXPECT_FALSE(d.explanation.empty());
    EXPECT_FALSE(d.parameters.empty());
  }
  const std::vector<std::string> expected = {
      "accel:lever_arm",  "both:time_offset",       "gyro:g_sensitivity", "gyro:bias_instability",
      "gyro:white_noise", "accel:bias_random_walk", "accel:white_noise",  "accel:quantization"};
  EXPECT_EQ(names, expected);
}

TEST(ImuErrorModel, ValidateNamesTheOffendingKey) {
  auto message = [](const ImuErrorModel& m) {
    try {
      m.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ImuErrorModel a;
  a.gyro.non_orthogonality.N(1, 1) = 1e-3;
  EXPECT_NE(message(a).find("gyro.non_orthogonality.N(1,1)"), std::string::npos) << message(a);
  ImuErrorModel b;
  b.accel.bias_instability.tau_s = -5.0;
  EXPECT_NE(message(b).find("accel.bias_instability.tau_s"), std::string::npos) << message(b);
  ImuErrorModel c;
  c.accel.vibration_rectification.coeff.x() = 1e-3;
  c.accel.vibration_rectification.regressor = "vibes";
  EXPECT_NE(message(c).find("vibes"), std::string::npos) << message(c);
  ImuErrorModel d;
  d.gyro.white_noise.density.y() = -1.0;
  EXPECT_NE(message(d).find("gyro.white_noise.density[1]"), std::string::npos) << message(d);
  EXPECT_THROW(applyErrors(constantSeries(2, 0.01, kOmega, kF), d, 1), std::invalid_argument);
}

TEST(ImuErrorModel, ProfileMapsToStochasticTermsAndSeededTurnOnErrors) {
  ImuProfile p;
  p.arw_rad_sqrt_s = 1e-4;
  p.vrw_m_s_sqrt_s = 2e-3;
  p.gyro_bias_instability_rad_s = 5e-6;
  p.accel_bias_instability_m_s2 = 5e-4;
  p.gyro_bias_corr_time_s = 1800.0;
  p.accel_scale_std = 1e-3;
  const ImuErrorModel s = stochasticErrorModel(p);
  EXPECT_EQ(s.gyro.white_noise.density, Vector3d::Constant(1e-4));
  EXPECT_EQ(s.accel.white_noise.density, Vector3d::Constant(2e-3));
  EXPECT_EQ(s.gyro.bias_instability.sigma, Vector3d::Constant(5e-6));
  EXPECT_EQ(s.gyro.bias_instability.tau_s, 1800.0);
  EXPECT_FALSE(s.gyro.constant_bias.isActive());
  const ImuErrorModel a = sampleErrorModel(p, 3), b = sampleErrorModel(p, 3),
                      c = sampleErrorModel(p, 4);
  EXPECT_EQ(a.gyro.constant_bias.b, b.gyro.constant_bias.b);
  EXPECT_NE(a.gyro.constant_bias.b, c.gyro.constant_bias.b);
  EXPECT_TRUE(a.accel.scale_factor.isActive());
  EXPECT_FALSE(a.gyro.scale_factor.isActive());  // gyro_scale_std = 0
  EXPECT_LT(a.gyro.constant_bias.b.cwiseAbs().maxCoeff(), 6.0 * 5e-6);
}

}  // namespace
}  // namespace graftnav
