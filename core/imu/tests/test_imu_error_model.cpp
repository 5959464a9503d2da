// Each deterministic IMU error term against its analytic effect, quantization, and the error
// model's determinism and composition (geometry and stochastic terms: test_imu_geometry.cpp,
// test_imu_stochastic.cpp).
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
