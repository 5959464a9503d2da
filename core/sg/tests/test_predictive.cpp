// Quantiles, REAL's percentile, DIFF intervals and verdicts against hand computation.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "graftnav/sg/predictive.h"
#include "graftnav/sg/sg_statistics.h"

namespace graftnav {
namespace {

TEST(Predictive, WeibullQuantilesByHand) {
  std::vector<double> v;
  for (int i = 19; i >= 1; --i) v.push_back(i);  // unsorted on purpose
  // K = 19: rank p (K + 1) = 1, 10, 19 for p = 0.05, 0.5, 0.95.
  EXPECT_DOUBLE_EQ(weibullQuantile(v, 0.05), 1.0);
  EXPECT_DOUBLE_EQ(weibullQuantile(v, 0.50), 10.0);
  EXPECT_DOUBLE_EQ(weibullQuantile(v, 0.95), 19.0);
  // K = 4: the median sits at rank 2.5, half-way between 20 and 30; p05 clamps to the minimum.
  EXPECT_DOUBLE_EQ(weibullQuantile({40, 10, 30, 20}, 0.5), 25.0);
  EXPECT_DOUBLE_EQ(weibullQuantile({40, 10, 30, 20}, 0.05), 10.0);
  EXPECT_DOUBLE_EQ(weibullQuantile({40, 10, 30, 20}, 0.95), 40.0);
  // K = 20: rank 1.05 and 19.95.
  std::vector<double> w;
  for (int i = 1; i <= 20; ++i) w.push_back(10.0 * i);
  EXPECT_NEAR(weibullQuantile(w, 0.05), 10.5, 1e-12);
  EXPECT_NEAR(weibullQuantile(w, 0.95), 199.5, 1e-12);
  EXPECT_THROW(weibullQuantile({}, 0.5), std::invalid_argument);
  EXPECT_THROW(weibullQuantile({1.0, NAN}, 0.5), std::invalid_argument);
  EXPECT_THROW(weibullQuantile({1.0}, 1.5), std::invalid_argument);
}

TEST(Predictive, SummaryMeanAndSampleSd) {
  const PredictiveSummary s = summarizeDraws({2, 4, 4, 4, 5, 5, 7, 9});
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_NEAR(s.sd, std::sqrt(32.0 / 7.0), 1e-12);
  EXPECT_EQ(s.count, 8);
  EXPECT_DOUBLE_EQ(s.p50, 4.5);  // rank 4.5 between 4 and 5
}

TEST(Predictive, RealPercentileCountsTiesHalf) {
  EXPECT_DOUBLE_EQ(realPercentile({1, 2, 3, 4}, 2.5), 0.5);
  EXPECT_DOUBLE_EQ(realPercentile({1, 2, 3, 4}, 2.0), 0.375);
  EXPECT_DOUBLE_EQ(realPercentile({1, 2, 3, 4}, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(realPercentile({1, 2, 3, 4}, 9.0), 1.0);
}

TEST(Predictive, VerdictsAtTheIntervalEdges) {
  PredictiveSummary s;
  s.p05 = 1.0;
  s.p95 = 3.0;
  EXPECT_EQ(verdictFor(s, 3.5), Verdict::kOptimistic);
  EXPECT_EQ(verdictFor(s, 0.5), Verdict::kPessimistic);
  EXPECT_EQ(verdictFor(s, 2.0), Verdict::kConsistent);
  EXPECT_EQ(verdictFor(s, 3.0), Verdict::kConsistent);  // closed interval
  EXPECT_STREQ(verdictName(Verdict::kOptimistic), "optimistic");
}

TEST(Predictive, DiffIntervalByHand) {
  // DIFF_k = |x - 1| / 1 = {0.2, 0.1, 0, 0.1, 0.2, 0.5}; K = 6 clamps both ranks to the extremes.
  const auto d = diffInterval({0.8, 0.9, 1.0, 1.1, 1.2, 1.5}, 1.0);
  EXPECT_NEAR(d[0], 0.0, 1e-12);
  EXPECT_NEAR(d[1], 0.5, 1e-12);
  EXPECT_THROW(diffInterval({1.0}, 0.0), std::invalid_argument);
}

TEST(Predictive, StatsPerStatisticWithVerdicts) {
  // 19 draws with horizontal 1..19 m and the angles fixed; REAL horizontal 25 m (above p95 = 19).
  std::vector<DriftStats> draws;
  for (int i = 1; i <= 19; ++i)
    draws.push_back(fromArray({double(i), 2.0 + 0.125 * i, 0.001, 0.002, 0.003}));
  const DriftStats real = fromArray({25.0, 3.25, 0.001, 0.0001, 0.0});
  const PredictiveStats p = predictiveStats(draws, &real);
  EXPECT_EQ(p.verdict[0], Verdict::kOptimistic);
  EXPECT_DOUBLE_EQ(p.real_percentile[0], 1.0);
  EXPECT_EQ(p.verdict[1], Verdict::kConsistent);         // 3.25 (draw 10) inside [2.125, 4.375]
  EXPECT_NEAR(p.real_percentile[1], 9.5 / 19.0, 1e-12);  // 9 below, one tie
  EXPECT_EQ(p.verdict[2], Verdict::kConsistent);         // every draw ties with REAL
  EXPECT_EQ(p.verdict[3], Verdict::kPessimistic);
  EXPECT_FALSE(p.real_valid[4]);  // ERR_REAL of zero: no percentile, DIFF or verdict
  EXPECT_TRUE(p.real_valid[0]);
  EXPECT_NEAR(p.diff_interval[0][0], 6.0 / 25.0, 1e-12);   // smallest |x - 25| / 25
  EXPECT_NEAR(p.diff_interval[0][1], 24.0 / 25.0, 1e-12);  // largest
  EXPECT_NEAR(meanDriftStats(draws).horizontal_m, 10.0, 1e-12);
}

}  // namespace
}  // namespace graftnav
