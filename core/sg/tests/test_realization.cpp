// The realization draws have the stated statistics: turn-on bias sd, disjoint segments where the
// record allows, distinct offsets modulo the mirror period otherwise, Gauss-Markov wander, seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

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
}

TEST(Realization, WanderBeyondTheRecordIsGaussMarkovFromZero) {
  const BasicErrorSignal basic = record(6000, 0.01);  // T = 60 s
  RealizationOptions o;
  o.count = 3000;
  o.vary_turn_on_bias = false;
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
    EXPECT_TRUE((b[k].dtheta_rad - a[k].dtheta_rad).isApprox(on.power_on.gyro_bias_rad_s * 0.01, 1e-9));
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
