#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "graftnav/sg/grafting.h"

namespace graftnav {
namespace {

ImuSeries series(const std::vector<double>& gyro_x_rate, double dt, double t0 = 0.0) {
  ImuSeries s;
  double t = t0;
  for (double r : gyro_x_rate) {
    t += dt;
    ImuSample x;
    x.t_s = t;
    x.dt_s = dt;
    x.dtheta_rad = Eigen::Vector3d(r * dt, 0.0, 0.0);
    x.dvel_m_s = Eigen::Vector3d(0.0, 0.0, -2.0 * r * dt);
    s.push_back(x);
  }
  return s;
}

TEST(Grafting, MirroredTilingOnHandMadeCase) {
  // Lab error rates 1, 2, 3 (rad/s) for 1 s each: tiled 1 2 3 | 3 2 1 | 1 2 3 ...
  const BasicErrorSignal basic(series({1, 2, 3}, 1.0));
  EXPECT_DOUBLE_EQ(basic.recordLength_s(), 3.0);
  EXPECT_DOUBLE_EQ(basic.meanGyro_rad_s().x(), 2.0);
  const ImuSeries ref = series({0, 0, 0, 0, 0, 0, 0, 0}, 1.0, 100.0);
  GraftOptions opt;
  opt.start_offset_s = 0.0;
  const ImuSeries sg1 = graftBasic(ref, basic, opt);
  const std::vector<double> expected{1, 2, 3, 3, 2, 1, 1, 2};
  ASSERT_EQ(sg1.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_NEAR(sg1[k].dtheta_rad.x(), expected[k], 1e-12) << k;
    EXPECT_NEAR(sg1[k].dvel_m_s.z(), -2.0 * expected[k], 1e-12) << k;
    EXPECT_DOUBLE_EQ(sg1[k].t_s, ref[k].t_s);
  }
}

TEST(Grafting, IntervalsNeedNotMatchTheLabRate) {
  // The same lab signal sampled at 2 Hz, grafted on 1 Hz reference samples with a half-second
  // offset: each increment is the exact integral of the tiled rate over its interval.
  const BasicErrorSignal basic(series({1, 1, 2, 2, 3, 3}, 0.5));
  const ImuSeries ref = series({10, 10, 10, 10}, 1.0);
  GraftOptions opt;
  opt.start_offset_s = 0.5;
  const ImuSeries sg1 = graftBasic(ref, basic, opt);
  // u intervals (0.5,1.5], (1.5,2.5], (2.5,3.5], (3.5,4.5] over rates 1 2 3 | 3 2 1.
  const std::vector<double> expected{1.5, 2.5, 3.0, 2.5};
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_NEAR(sg1[k].dtheta_rad.x(), 10.0 + expected[k], 1e-12) << k;
}

TEST(Grafting, TiledIntegralIsContinuousAndConservesTheRecord) {
  const BasicErrorSignal basic(series({0.3, -0.1, 0.7, 0.2, 0.4}, 0.01));
  const double T = basic.recordLength_s();
  // Whole number of records carries the record's integral exactly, in either direction.
  EXPECT_NEAR(basic.integral(0.0, 4 * T)(0), 4 * basic.integral(0.0, T)(0), 1e-12);
  EXPECT_NEAR(basic.integral(T, 2 * T)(0), basic.integral(0.0, T)(0), 1e-12);
  // No jump at a seam: the rate just before and after 2T is the same sample (mirror).
  const double eps = 1e-4;
  EXPECT_NEAR(basic.integral(2 * T - eps, 2 * T)(0) / eps,
              basic.integral(2 * T, 2 * T + eps)(0) / eps, 1e-9);
}

TEST(Grafting, FullErrorAddsDynamicErrorsWithoutDoubleCountingBias) {
  const BasicErrorSignal basic(series({0.5, 0.5}, 1.0));  // bias 0.5 rad/s
  SensorDynamicFit gyro;
  // measured = 0.5 + 1.01 x + 0.002 x^2 on x; M carries a cross-axis term y <- 0.003 x.
  gyro.poly[0] = {0.5, 1.01, 0.002};
  gyro.M << 1.01, 0.0, 0.0,  //
      0.003, 1.0, 0.0,       //
      0.0, 0.0, 1.0;
  SensorDynamicFit accel;
  const ImuSeries ref = series({2.0, 2.0}, 1.0);
  GraftOptions opt;
  opt.start_offset_s = 0.0;
  const ImuSeries sg2 = graftFull(ref, basic, gyro, accel, opt);
  const double x = 2.0;
  EXPECT_NEAR(sg2[0].dtheta_rad.x(), x + 0.01 * x + 0.002 * x * x + 0.5, 1e-12);
  EXPECT_NEAR(sg2[0].dtheta_rad.y(), 0.003 * x, 1e-12);
  // With cross-axis terms switched off only the per-axis polynomial remains.
  gyro.use_cross_axis = false;
  EXPECT_NEAR(graftFull(ref, basic, gyro, accel, opt)[0].dtheta_rad.y(), 0.0, 1e-15);
  // The accelerometer with an identity fit is grafted like SG#1.
  EXPECT_NEAR(sg2[1].dvel_m_s.z(), graftBasic(ref, basic, opt)[1].dvel_m_s.z(), 1e-15);
}

TEST(Grafting, NoiseFreeFullGraftReproducesTheSensorModelExactly) {
  // Sensor: measured = M true + b. The lab static record sees true = x_s (gravity at the static
  // attitude), so its basic error is (M - I) x_s + b. SG#2 of any reference signal x must then be
  // exactly M x + b: no bias counted twice, no scale on gravity counted twice.
  Eigen::Matrix3d M;
  M << 1.0 + 300e-6, 40e-6, -25e-6,  //
      30e-6, 1.0 - 180e-6, 15e-6,    //
      -35e-6, 20e-6, 1.0 + 120e-6;
  const Eigen::Vector3d b(0.003, -0.004, 0.002);
  const Eigen::Vector3d x_s(0.0, 0.0, -9.79);
  const double dt = 0.01;
  ImuSeries lab;
  for (int k = 1; k <= 10; ++k) {
    ImuSample s;
    s.t_s = k * dt;
    s.dt_s = dt;
    s.dvel_m_s = ((M - Eigen::Matrix3d::Identity()) * x_s + b) * dt;
    lab.push_back(s);
  }
  const BasicErrorSignal basic(lab);
  SensorDynamicFit accel;
  for (int i = 0; i < 3; ++i) accel.poly[i] = {b[i], M(i, i)};
  accel.M = M;
  accel.static_point = x_s;
  ImuSeries ref;
  const std::vector<Eigen::Vector3d> xs{{1.5, -0.3, -9.7}, {-2.0, 3.1, -10.4}, {0.0, 0.0, -9.79}};
  for (std::size_t k = 0; k < xs.size(); ++k) {
    ImuSample s;
    s.t_s = 50.0 + (k + 1) * dt;
    s.dt_s = dt;
    s.dvel_m_s = xs[k] * dt;
    ref.push_back(s);
  }
  GraftOptions opt;
  opt.start_offset_s = 0.0;
  const ImuSeries sg2 = graftFull(ref, basic, SensorDynamicFit{}, accel, opt);
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const Eigen::Vector3d expected = M * xs[k] + b;
    EXPECT_LT((sg2[k].dvel_m_s / dt - expected).norm(), 1e-12) << k;
  }
}

std::vector<double> pseudoNoise(std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t k = 0; k < n; ++k) v[k] = std::sin(0.7 * k * k + 0.3 * k);  // white-like
  return v;
}

TEST(Grafting, DeterministicForASeedAndDifferentAcrossSeeds) {
  const BasicErrorSignal basic(series(pseudoNoise(64), 0.5));
  const ImuSeries ref = series({0, 0, 0}, 0.5);
  GraftOptions a;
  a.seed = 42;
  GraftOptions b = a;
  GraftOptions c = a;
  c.seed = 43;
  EXPECT_EQ(graftStartOffset(a, basic), graftStartOffset(b, basic));
  EXPECT_NE(graftStartOffset(a, basic), graftStartOffset(c, basic));
  const ImuSeries ya = graftBasic(ref, basic, a), yb = graftBasic(ref, basic, b);
  for (std::size_t k = 0; k < ya.size(); ++k) EXPECT_EQ(ya[k].dtheta_rad, yb[k].dtheta_rad);
}

TEST(Grafting, SeededStartKeepsEachLabSampleWhole) {
  // Equal lab and field rates: whatever the seed, every grafted increment must be one lab
  // increment, not a blend of two neighbours (a blend lowers the per-sample noise while keeping
  // its random walk, so the grafted IMU would look quieter than the lab record at 200 Hz).
  const double dt = 0.005;
  const std::vector<double> lab = pseudoNoise(400);
  const BasicErrorSignal basic(series(lab, dt));
  const ImuSeries ref = series(std::vector<double>(250, 0.0), dt, 1234.5);
  double lab_ms = 0.0;
  for (double r : lab) lab_ms += r * r / lab.size();
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    GraftOptions opt;
    opt.seed = seed;
    const ImuSeries sg1 = graftBasic(ref, basic, opt);
    double sg_ms = 0.0;
    for (const ImuSample& s : sg1) {
      const double rate = s.dtheta_rad.x() / dt;
      double nearest = 1e9;
      for (double r : lab) nearest = std::min(nearest, std::abs(rate - r));
      ASSERT_LT(nearest, 1e-6) << "seed " << seed << " t " << s.t_s;
      sg_ms += rate * rate / sg1.size();
    }
    EXPECT_NEAR(sg_ms / lab_ms, 1.0, 0.25) << "seed " << seed;
  }
}

// Six channels of noise with a bias, on jittered sample lengths (n samples).
ImuSeries jitteredNoise(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1e-3);
  std::uniform_real_distribution<double> jitter(0.9, 1.1);
  ImuSeries s;
  double t = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    ImuSample x;
    x.dt_s = 0.005 * jitter(rng);
    t += x.dt_s;
    x.t_s = t;
    x.dtheta_rad = Eigen::Vector3d(2e-4 + g(rng), g(rng), g(rng)) * x.dt_s;
    x.dvel_m_s = Eigen::Vector3d(g(rng), 0.01 + g(rng), g(rng)) * x.dt_s;
    s.push_back(x);
  }
  return s;
}

TEST(Grafting, ASpooledSurrogateGivesTheHeldOnesValuesBitForBit) {
  // 3000 samples: a surrogate of 6000, read back from its spool in windows of 4096 samples.
  const BasicErrorSignal record(jitteredNoise(3000, 5));
  SlowNoiseModel slow;
  slow.white_density.setConstant(1e-4);
  slow.wander_sigma.setConstant(1e-4);
  slow.slow_period_s = 2.0;
  const std::vector<const SlowNoiseModel*> models{nullptr, &slow};
  for (const SlowNoiseModel* model : models) {
    const BasicErrorSignal held = record.phaseRandomized(99, model);
    const BasicErrorSignal spooled = record.phaseRandomizedSpooled(99, model);
    EXPECT_FALSE(held.spooled());
    ASSERT_TRUE(spooled.spooled());
    ASSERT_EQ(spooled.sampleCount(), held.sampleCount());
    ASSERT_GT(held.sampleCount(), BasicErrorSignal::kWindow + 1);
    EXPECT_EQ(spooled.recordLength_s(), held.recordLength_s());
    EXPECT_EQ(spooled.meanGyro_rad_s(), held.meanGyro_rad_s());
    EXPECT_EQ(spooled.meanAccel_m_s2(), held.meanAccel_m_s2());
    // Forward through three tiles (the middle one read backwards), then jumps back and forth.
    const double T = held.recordLength_s();
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 3.0 * T);
    for (double u0 = 0.0; u0 < 3.0 * T; u0 += 0.0049) {
      ASSERT_EQ(spooled.integral(u0, u0 + 0.005), held.integral(u0, u0 + 0.005)) << u0;
    }
    for (int i = 0; i < 2000; ++i) {
      const double a = u(rng), b = a + 0.1 * u(rng);
      ASSERT_EQ(spooled.integral(a, b), held.integral(a, b)) << a << " " << b;
      ASSERT_EQ(spooled.sampleBoundaryAtOrBefore(a), held.sampleBoundaryAtOrBefore(a)) << a;
    }
    const LabErrorRates hr = held.rates(), sr = spooled.rates();
    EXPECT_EQ(sr.rate, hr.rate);
    EXPECT_EQ(sr.dt_s, hr.dt_s);
  }
}

TEST(Grafting, ASpooledSurrogateGraftsTheHeldOnesSamples) {
  const BasicErrorSignal record(jitteredNoise(3000, 8));
  const ImuSeries ref = series(pseudoNoise(9000), 0.005, 50.0);
  GraftOptions held;
  held.seed = 17;
  held.surrogate_seed = 1234;
  GraftOptions spooled = held;
  spooled.spool_surrogate = true;
  const ImuSeries a = graftBasic(ref, record, held), b = graftBasic(ref, record, spooled);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].dtheta_rad, b[k].dtheta_rad) << k;
    ASSERT_EQ(a[k].dvel_m_s, b[k].dvel_m_s) << k;
  }
  GraftOptions nowhere = spooled;
  nowhere.spool_directory = "/nonexistent/graftnav";
  EXPECT_THROW(graftBasic(ref, record, nowhere), std::runtime_error);
}

TEST(Grafting, RejectsAnEmptyRecord) {
  EXPECT_THROW(BasicErrorSignal(series({1.0}, 1.0)), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
