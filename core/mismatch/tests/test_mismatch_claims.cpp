// What may be claimed: a value lattice against the printed resolution and the white noise
// (quantization_evidence.h), a fitted value against the sensor class's range (claim_checks.h),
// and the linear-response term that replaces mounting / scale / non-orthogonality.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graftnav/imu/plausible_ranges.h"
#include "graftnav/mismatch/claim_checks.h"
#include "graftnav/mismatch/linear_response.h"
#include "graftnav/mismatch/quantization_evidence.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {
namespace {

// 100-Hz gyro increments: white noise of sd_rad per sample, each value rounded to `lattice`
// (0: not rounded), as a counter or a text file would.
ImuSeries noisyIncrements(double sd_rad, double lattice, int n = 20000, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, sd_rad);
  ImuSeries s(n);
  for (int k = 0; k < n; ++k) {
    s[k].t_s = 0.01 * (k + 1);
    s[k].dt_s = 0.01;
    for (int a = 0; a < 3; ++a) {
      double v = g(rng);
      if (lattice > 0.0) v = std::round(v / lattice) * lattice;
      s[k].dtheta_rad(a) = v;
      s[k].dvel_m_s(a) = v;
    }
  }
  return s;
}

TEST(MismatchClaims, PrintedResolutionIsTheCoarsestPowerOfTenEveryValueSitsOn) {
  EXPECT_NEAR(printedResolution(noisyIncrements(3e-6, 1e-9), Sensor::gyro)(0), 1e-9, 1e-21);
  EXPECT_NEAR(printedResolution(noisyIncrements(3e-6, 1e-7), Sensor::gyro)(1), 1e-7, 1e-19);
  EXPECT_EQ(printedResolution(noisyIncrements(3e-6, 0.0), Sensor::gyro)(2), 0.0);
}

TEST(MismatchClaims, ALatticeAtThePrintedResolutionIsTheTextFormatNotTheSensor) {
  const ImuSeries sim = noisyIncrements(3e-6, 0.0, 20000, 5);
  // Fixed decimals at 1e-9: a lattice, but the text's own, and its noise is 1e-8 of the white's.
  const QuantizationCheck text = checkQuantization(noisyIncrements(3e-6, 1e-9), sim, Sensor::gyro);
  EXPECT_NEAR(text.step(0), 1e-9, 1e-15);
  EXPECT_NEAR(text.printed_resolution(0), 1e-9, 1e-21);
  EXPECT_FALSE(text.anyClaimed()) << text.summary();
  // A 4e-6 step (not a power of ten) with q^2/12 = 15 % of the white noise: claimed.
  const QuantizationCheck coarse =
      checkQuantization(noisyIncrements(3e-6, 4e-6), sim, Sensor::gyro);
  EXPECT_NEAR(coarse.step(0), 4e-6, 1e-12);
  EXPECT_TRUE(coarse.claimed[0] && coarse.claimed[1] && coarse.claimed[2]) << coarse.summary();
  EXPECT_GT(coarse.noise_share(0), coarse.resolvable_share);
  // A 2e-7 step under 3e-5 of white noise: beyond the printing but not resolvable, and the
  // step it would need is stated.
  const QuantizationCheck fine = checkQuantization(noisyIncrements(3e-5, 2e-7), sim, Sensor::gyro);
  EXPECT_NEAR(fine.step(0), 2e-7, 1e-13);
  EXPECT_FALSE(fine.anyClaimed()) << fine.summary();
  EXPECT_GT(fine.detectable_step(0), fine.step(0));
}

TEST(MismatchClaims, AFittedValueOutsideTheClassRangeIsFound) {
  const PlausibleRanges consumer = plausibleRangesForClass("consumer_mems");
  Effect e(termSpec(TermKind::scale_factor), SensorScope::accel);
  EffectParameter k;
  k.key = "k";
  k.values = {0.007, 0.18, -0.012};
  k.sigma = {0.005, 0.011, 0.08};
  e.parameters.push_back(k);
  const std::optional<RangeExcess> x = outsidePlausibleRange(e, consumer);
  ASSERT_TRUE(x.has_value());
  EXPECT_EQ(x->parameter, "k");
  EXPECT_DOUBLE_EQ(x->value, 0.18);
  EXPECT_DOUBLE_EQ(x->bound, consumer.accel_scale_max);
  e.parameters[0].values = {0.007, 0.01, -0.012};
  EXPECT_FALSE(outsidePlausibleRange(e, consumer).has_value());
  // The same 1 % is beyond a navigation-grade sensor's range.
  EXPECT_TRUE(outsidePlausibleRange(e, plausibleRangesForClass("navigation")).has_value());
  // The combined effect bounds only its diagonal (the scale part): a 4-deg rotation is fine.
  Effect lin(termSpec(TermKind::mounting_scale_nonorthogonality), SensorScope::both);
  EffectParameter E;
  E.key = "E_gyro";
  E.values = {0.001, 0.07, 0.0, -0.07, 0.002, 0.0, 0.0, 0.0, 0.001};
  E.sigma.assign(9, 0.001);
  lin.parameters.push_back(E);
  EXPECT_FALSE(outsidePlausibleRange(lin, consumer).has_value());
  lin.parameters[0].values[4] = 0.05;
  EXPECT_TRUE(outsidePlausibleRange(lin, consumer).has_value());
}

TEST(MismatchClaims, ClassesAreOrderedAndUnknownOnesRefused) {
  const PlausibleRanges c = plausibleRangesForClass("consumer_mems"),
                        t = plausibleRangesForClass("tactical"),
                        n = plausibleRangesForClass("navigation");
  for (const PlausibleRanges* r : {&c, &t, &n}) {
    EXPECT_NO_THROW(r->validate());
    EXPECT_FALSE(r->source.empty());
  }
  EXPECT_GT(c.gyro_scale_max, t.gyro_scale_max);
  EXPECT_GT(t.gyro_scale_max, n.gyro_scale_max);
  EXPECT_GT(c.g_sensitivity_max_rad_s_per_m_s2, t.g_sensitivity_max_rad_s_per_m_s2);
  EXPECT_THROW(plausibleRangesForClass("phone"), std::invalid_argument);
  EXPECT_EQ(sensorClassForGrade(ImuGrade::kMems), "consumer_mems");
}

TEST(MismatchClaims, LinearResponseTermHasOneColumnPerMatrixElementOfEachSensor) {
  BinnedImu x;
  x.grid.count = 4;
  x.omega_rad_s = Eigen::MatrixX3d::Random(4, 3);
  x.f_m_s2 = Eigen::MatrixX3d::Random(4, 3);
  const CandidateTerm t = linearResponseTerm(x);
  ASSERT_EQ(t.columns.size(), 18u);
  // E_accel(1, 2): channel accel y, column f_z.
  EXPECT_TRUE(t.columns[9 + 5].actsOn(4));
  EXPECT_EQ(t.columns[9 + 5].channel[4], x.f_m_s2.col(2));
  EXPECT_FALSE(t.columns[9 + 5].actsOn(3));
}

}  // namespace
}  // namespace graftnav
