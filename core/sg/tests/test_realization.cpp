// The realization draws have the stated statistics: turn-on bias sd, disjoint segments where the
// record allows, distinct offsets modulo the mirror period and an independent surrogate of the lab
// noise otherwise, Gauss-Markov wander, seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <set>
#include <vector>

#include "graftnav/sg/noise_surrogate.h"
#include "graftnav/sg/realization.h"

namespace graftnav {
namespace {

// A lab error record of n samples of dt seconds with random rates.
BasicErrorSignal record(int n, double dt) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 1e-3);
  ImuSeries s;
  for (int k = 0; k < n; ++k) {
    ImuSample x;
    x.dt_s = dt;
    x.t_s = (k + 1) * dt;
    x.dtheta_rad = Eigen::Vector3d(g(rng), g(rng), g(rng)) * dt;
    x.dvel_m_s = Eigen::Vector3d(g(rng), g(rng), g(rng)) * dt;
    s.push_back(x);
  }
  return BasicErrorSignal(s);
}

ImuProfile profile() {
  ImuProfile p;
  p.gyro_bias_instability_rad_s = 2e-5;
  p.accel_bias_instability_m_s2 = 3e-3;
  p.gyro_bias_corr_time_s = 600.0;
  p.accel_bias_corr_time_s = 600.0;
  p.gyro_bias_repeatability_rad_s = 1e-4;
  p.accel_bias_repeatability_m_s2 = 1e-2;
  return p;
}

double sampleSd(const std::vector<double>& v) {
  double m = 0.0, ss = 0.0;
  for (double x : v) m += x;
  m /= v.size();
  for (double x : v) ss += (x - m) * (x - m);
  return std::sqrt(ss / (v.size() - 1));
}

TEST(Realization, TurnOnBiasHasTheRepeatabilityOfOneMoreSession) {
  const BasicErrorSignal basic = record(1000, 0.01);
  for (int sessions : {1, 3}) {
    RealizationOptions o;
    o.count = 4000;
    o.lab_sessions = sessions;
    const auto draws = drawRealizations(o, basic, profile(), 5.0);
    std::vector<double> g, a;
    for (const auto& d : draws) {
      g.push_back(d.power_on.gyro_bias_rad_s.y());
      a.push_back(d.power_on.accel_bias_m_s2.z());
    }
    const double factor = std::sqrt(1.0 + 1.0 / sessions);
    // sd of a sample sd of 4000 normal draws: 1.1 %; 5 % is about 4.5 sigma.
    EXPECT_NEAR(sampleSd(g) / (1e-4 * factor), 1.0, 0.05) << sessions;
    EXPECT_NEAR(sampleSd(a) / (1e-2 * factor), 1.0, 0.05) << sessions;
  }
}

TEST(Realization, RepeatabilityDefaultsToTheBiasInstability) {
  ImuProfile p = profile();
  p.gyro_bias_repeatability_rad_s = -1.0;
  RealizationOptions o;
  o.count = 4000;
  const auto draws = drawRealizations(o, record(1000, 0.01), p, 5.0);
  std::vector<double> g;
  for (const auto& d : draws) g.push_back(d.power_on.gyro_bias_rad_s.x());
  EXPECT_NEAR(sampleSd(g) / (2e-5 * std::sqrt(2.0)), 1.0, 0.05);
}

TEST(Realization, DisjointSegmentsWhenTheRecordHoldsThemAll) {
  const BasicErrorSignal basic = record(100000, 0.01);  // T = 1000 s
  RealizationOptions o;
  o.count = 20;
  const double span = 40.0;  // 20 x 40 s = 800 s <= T
  const auto draws = drawRealizations(o, basic, profile(), span);
  std::vector<double> off;
  for (const auto& d : draws) off.push_back(d.start_offset_s);
  std::sort(off.begin(), off.end());
  for (std::size_t k = 1; k < off.size(); ++k) EXPECT_GE(off[k] - off[k - 1], span - 1e-9) << k;
  EXPECT_LE(off.back() + span, basic.recordLength_s() + 1e-9);
  EXPECT_GE(off.front(), 0.0);
  EXPECT_DOUBLE_EQ(sharedSampleFraction(draws, basic), 0.0);
  EXPECT_TRUE(draws.front().power_on.wander_knots.empty());  // the record holds the wander
  for (const auto& d : draws)
    EXPECT_FALSE(d.surrogate_seed) << "a long record grafts its own noise";
}

TEST(Realization, ShortRecordOffsetsAreStratifiedOverTheMirrorPeriodOnSampleBoundaries) {
  const BasicErrorSignal basic = record(12000, 0.01);  // T = 120 s, the bundled samples' length
  RealizationOptions o;
  o.count = 20;
  const auto draws = drawRealizations(o, basic, profile(), 390.0);
  const double T = basic.recordLength_s(), stratum = 2.0 * T / o.count;
  for (const auto& d : draws) {
    EXPECT_GE(d.start_offset_s, d.index * stratum - 0.01 - 1e-9) << d.index;
    EXPECT_LT(d.start_offset_s, (d.index + 1) * stratum) << d.index;
    const double samples = d.start_offset_s / 0.01;
    EXPECT_NEAR(samples, std::round(samples), 1e-6) << "not on a lab sample boundary";
  }
  EXPECT_DOUBLE_EQ(sharedSampleFraction(draws, basic), 0.0);
  std::set<std::uint64_t> seeds;
  for (const auto& d : draws) {
    ASSERT_TRUE(d.surrogate_seed) << "a short record needs a surrogate per realization";
    seeds.insert(*d.surrogate_seed);
  }
  EXPECT_EQ(seeds.size(), draws.size());
  o.surrogate_short_record = false;
  for (const auto& d : drawRealizations(o, basic, profile(), 390.0)) EXPECT_FALSE(d.surrogate_seed);
}

TEST(Realization, RecordAsLongAsTheFieldTestTakesOffsetsOfItselfNotASurrogate) {
  RealizationOptions o;
  o.count = 20;
  const BasicErrorSignal as_long = record(40000, 0.01);  // T = 400 s > the field span
  for (const auto& d : drawRealizations(o, as_long, profile(), 390.0))
    EXPECT_FALSE(d.surrogate_seed) << d.index;
  const BasicErrorSignal shorter = record(38000, 0.01);  // T = 380 s
  for (const auto& d : drawRealizations(o, shorter, profile(), 390.0))
    EXPECT_TRUE(d.surrogate_seed) << d.index;
}

// A record with slow content (a random walk) and white noise, as a lab static record has.
BasicErrorSignal slowRecord(int n, double dt) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  ImuSeries s;
  Eigen::Matrix<double, 6, 1> walk = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < 6; ++i) walk[i] += 2e-5 * g(rng);
    ImuSample x;
    x.dt_s = dt;
    x.t_s = (k + 1) * dt;
    for (int i = 0; i < 3; ++i) {
      x.dtheta_rad[i] = (1e-4 + walk[i] + 1e-4 * g(rng)) * dt;
      x.dvel_m_s[i] = (3e-3 + walk[3 + i] + 2e-3 * g(rng)) * dt;
    }
    s.push_back(x);
  }
  return BasicErrorSignal(s);
}

// Over many surrogate draws, the sum of the error over a 0.25 s window has the sd of the record's
// own windows (all circular shifts of the mirrored record), and two draws are uncorrelated.
TEST(Realization, SurrogateWindowsHaveTheRecordsSpreadAndAreIndependent) {
  const int n = 250, w = 25;  // 2 n = 500 = 2^2 5^3: the mirrored record is used whole
  const BasicErrorSignal basic = slowRecord(n, 0.01);
  const LabErrorRates rec = basic.rates();
  std::vector<double> mirrored(2 * n);
  for (int j = 0; j < 2 * n; ++j) mirrored[j] = rec.rate[j < n ? j : 2 * n - 1 - j][4];
  double mean = 0.0;
  for (double x : mirrored) mean += x;
  mean /= 2 * n;
  double ss = 0.0;
  for (int s0 = 0; s0 < 2 * n; ++s0) {
    double sum = 0.0;
    for (int j = 0; j < w; ++j) sum += mirrored[(s0 + j) % (2 * n)] - mean;
    ss += sum * sum;
  }
  const double expected_sd = std::sqrt(ss / (2 * n));
  std::vector<double> a, b;
  for (std::uint64_t seed = 1; seed <= 4000; ++seed) {
    const LabErrorRates s = phaseRandomizedSurrogate(rec, seed);
    double sum = 0.0;
    for (int j = 100; j < 100 + w; ++j) sum += s.rate[j][4] - mean;
    (seed % 2 ? a : b).push_back(sum);
  }
  std::vector<double> all = a;
  all.insert(all.end(), b.begin(), b.end());
  EXPECT_NEAR(sampleSd(all) / expected_sd, 1.0, 0.05);
  double sab = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sab += a[k] * b[k];
  const double corr = sab / (a.size() * sampleSd(a) * sampleSd(b));
  EXPECT_LT(std::fabs(corr), 0.06) << "surrogates of two seeds must be independent";
}

// The slow content of a surrogate is the model's: over 4000 draws from a record without any slow
// content, the sum over a window has the sd that the model's bins give it (analytic), and the
// wander knots start only beyond the surrogate's period 2T.
TEST(Realization, SurrogateSlowContentHasTheModelsSpread) {
  const int n = 250, m = 2 * n, w = 60, j0 = 40;
  const double dt = 0.01;
  LabErrorRates rec;
  rec.rate.assign(n, Eigen::Matrix<double, 6, 1>::Zero());
  rec.dt_s.assign(n, dt);
  SlowNoiseModel model;
  model.white_density.setConstant(1e-4);
  model.wander_sigma.setConstant(2e-3);
  model.wander_tau_s.setConstant(2.0);
  model.slow_period_s = 0.4;  // bins k < m dt / 0.4 = 12.5
  double expected_var = 0.0;
  for (int k = 1; 2 * k < m && m * dt / k > model.slow_period_s; ++k) {
    std::complex<double> g = 0.0;
    for (int j = j0; j < j0 + w; ++j) g += std::polar(1.0, 2.0 * M_PI * j * k / m);
    expected_var +=
        2.0 / (double(m) * m) * std::norm(g) * model.binPower(2, 2.0 * M_PI * k / m, m, dt);
  }
  std::vector<double> sums;
  for (std::uint64_t seed = 1; seed <= 4000; ++seed) {
    const LabErrorRates s = phaseRandomizedSurrogate(rec, seed, &model);
    double sum = 0.0;
    for (int j = j0; j < j0 + w; ++j) sum += s.rate[j][2];
    sums.push_back(sum);
  }
  EXPECT_NEAR(sampleSd(sums) / std::sqrt(expected_var), 1.0, 0.05);

  RealizationOptions o;
  o.count = 20;
  ImuProfile p = profile();
  p.arw_rad_sqrt_s = 1e-4;
  p.vrw_m_s_sqrt_s = 1e-3;
  const BasicErrorSignal basic = record(6000, 0.01);  // T = 60 s
  for (double span : {100.0, 300.0}) {
    const auto draws = drawRealizations(o, basic, p, span);
    ASSERT_TRUE(draws.front().slow_noise);
    EXPECT_DOUBLE_EQ(draws.front().slow_noise->slow_period_s, 20.0);
    EXPECT_NEAR(draws.front().slow_noise->wander_sigma[0], p.gyro_bias_instability_rad_s, 1e-15);
    if (span < 120.0)
      EXPECT_TRUE(draws.front().power_on.wander_knots.empty()) << "within 2T: the surrogate";
    else
      EXPECT_NEAR(draws.front().power_on.wander_step_s, 120.0, 1e-9);
  }
}

TEST(Realization, GraftingASurrogateKeepsTheLabBiasButNotTheNoise) {
  const BasicErrorSignal basic = slowRecord(1000, 0.01);
  ImuSeries ref;
  for (int k = 0; k < 2000; ++k) {
    ImuSample s;
    s.dt_s = 0.01;
    s.t_s = (k + 1) * 0.01;
    s.dvel_m_s = Eigen::Vector3d(0.0, 0.0, -9.8) * 0.01;
    ref.push_back(s);
  }
  GraftOptions plain;
  plain.start_offset_s = 0.0;
  GraftOptions other = plain;
  other.surrogate_seed = 5;
  const ImuSeries a = graftBasic(ref, basic, plain), b = graftBasic(ref, basic, other);
  // The first 2 T = 20 s of each hold the mirrored record or one whole surrogate period.
  Eigen::Vector3d sum_a = Eigen::Vector3d::Zero(), sum_b = Eigen::Vector3d::Zero();
  double differ = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    sum_a += a[k].dtheta_rad;
    sum_b += b[k].dtheta_rad;
    differ += std::fabs(a[k].dtheta_rad.x() - b[k].dtheta_rad.x());
  }
  EXPECT_TRUE(sum_b.isApprox(sum_a, 1e-9))
      << "the surrogate keeps the record's mean bias: " << sum_a.transpose() << " vs "
      << sum_b.transpose();
  EXPECT_GT(differ / 2000, 0.5e-4 * 0.01) << "but its noise is another realization";
}

TEST(Realization, WanderBeyondTheRecordIsGaussMarkovFromZero) {
  const BasicErrorSignal basic = record(6000, 0.01);  // T = 60 s
  RealizationOptions o;
  o.count = 3000;
  o.vary_turn_on_bias = false;
  o.slow_period_s = 0.0;  // the record's own spectrum: it holds the wander up to T
  const ImuProfile p = profile();
  const auto draws = drawRealizations(o, basic, p, 600.0);  // knots every 60 s, 11 of them
  std::vector<double> last;
  for (const auto& d : draws) {
    ASSERT_EQ(d.power_on.wander_knots.size(), 11u);
    EXPECT_EQ(d.power_on.wander_knots.front(), PowerOnErrors::Vec6::Zero());
    EXPECT_NEAR(d.power_on.wander_step_s, 60.0, 1e-9);
    last.push_back(d.power_on.wander_knots.back()[0]);
  }
  const double phi = std::exp(-60.0 / 600.0);
  const double expected = 2e-5 * std::sqrt(1.0 - std::pow(phi, 20));
  EXPECT_NEAR(sampleSd(last) / expected, 1.0, 0.06);
}

TEST(Realization, SameSeedSameDrawsOtherSeedOtherDraws) {
  const BasicErrorSignal basic = record(12000, 0.01);
  RealizationOptions o;
  o.count = 5;
  o.seed = 42;
  const auto a = drawRealizations(o, basic, profile(), 390.0);
  const auto b = drawRealizations(o, basic, profile(), 390.0);
  o.seed = 43;
  const auto c = drawRealizations(o, basic, profile(), 390.0);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(a[k].start_offset_s, b[k].start_offset_s);
    EXPECT_EQ(a[k].power_on.gyro_bias_rad_s, b[k].power_on.gyro_bias_rad_s);
    EXPECT_NE(a[k].power_on.gyro_bias_rad_s, c[k].power_on.gyro_bias_rad_s);
  }
}

TEST(Realization, GraftingAddsTheTurnOnBiasExactly) {
  const BasicErrorSignal basic = record(1000, 0.01);
  ImuSeries ref;
  for (int k = 0; k < 500; ++k) {
    ImuSample s;
    s.dt_s = 0.01;
    s.t_s = 1000.0 + (k + 1) * 0.01;
    s.dtheta_rad = Eigen::Vector3d(0.01, -0.02, 0.03) * 0.01;
    s.dvel_m_s = Eigen::Vector3d(0.1, 0.2, -9.8) * 0.01;
    ref.push_back(s);
  }
  GraftOptions plain;
  plain.start_offset_s = 1.0;
  GraftOptions on = plain;
  on.power_on.gyro_bias_rad_s = Eigen::Vector3d(1e-4, -2e-4, 3e-4);
  on.power_on.accel_bias_m_s2 = Eigen::Vector3d(-1e-2, 2e-2, 5e-3);
  const ImuSeries a = graftBasic(ref, basic, plain), b = graftBasic(ref, basic, on);
  for (std::size_t k = 0; k < ref.size(); ++k) {
    EXPECT_TRUE(
        (b[k].dtheta_rad - a[k].dtheta_rad).isApprox(on.power_on.gyro_bias_rad_s * 0.01, 1e-9));
    EXPECT_TRUE((b[k].dvel_m_s - a[k].dvel_m_s).isApprox(on.power_on.accel_bias_m_s2 * 0.01, 1e-9));
  }
}

TEST(Realization, OneRealizationIsTheSeedsSingleGraft) {
  RealizationOptions o;
  o.count = 1;
  const auto draws = drawRealizations(o, record(6000, 0.01), profile(), 600.0);
  ASSERT_EQ(draws.size(), 1u);
  EXPECT_TRUE(draws.front().power_on.empty());
}

TEST(Realization, OptionsAreValidated) {
  RealizationOptions o;
  o.count = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.count = 5;
  o.lab_sessions = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
