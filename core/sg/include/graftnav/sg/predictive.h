#pragma once
// ERR as a predictive distribution: K grafted realizations of one strategy (SG#1 or SG#2) give K
// values of each outage statistic; this file turns them into the numbers a user reads next to
// ERR_REAL: quantiles, REAL's percentile, the interval of DIFF and a verdict.
//
// Quantiles use the Weibull plotting position (Hyndman-Fan type 6): the p-quantile of K sorted
// draws sits at rank p (K + 1), linearly interpolated and clamped to [1, K]. For exchangeable
// draws a new draw falls below the value at rank r with probability r / (K + 1), so [p05, p95] is
// a 90 % prediction interval for one more realization - the question asked of ERR_REAL - as soon
// as K >= 19 (below that the ranks clamp and the interval covers (K - 1) / (K + 1)).

#include <array>
#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"

namespace graftnav {

struct PredictiveSummary {
  double p05 = 0.0, p50 = 0.0, p95 = 0.0, mean = 0.0, sd = 0.0;  // sd: sample (K - 1)
  int count = 0;
};

// Throws std::invalid_argument for an empty or non-finite sample, or p outside [0, 1].
double weibullQuantile(std::vector<double> values, double p);
PredictiveSummary summarizeDraws(const std::vector<double>& values);

// Fraction of draws strictly below `real`, ties counted half.
double realPercentile(const std::vector<double>& draws, double real);

enum class Verdict {
  kConsistent,   // ERR_REAL inside [p05, p95]
  kOptimistic,   // ERR_REAL above p95: the grafted IMU navigates better than the real one
  kPessimistic,  // ERR_REAL below p05: the grafted IMU navigates worse than the real one
};
const char* verdictName(Verdict v);  // "consistent", "optimistic", "pessimistic"
Verdict verdictFor(const PredictiveSummary& s, double real);

// 90 % interval [p05, p95] of the single-realization DIFF_k = |ERR_k - ERR_REAL| / ERR_REAL.
std::array<double, 2> diffInterval(const std::vector<double>& draws, double real);

// All of the above for the five statistics of one strategy.
struct PredictiveStats {
  std::array<PredictiveSummary, 5> summary;
  std::array<double, 5> real_percentile{};
  std::array<std::array<double, 2>, 5> diff_interval{};
  std::array<Verdict, 5> verdict{};
  // Per statistic: ERR_REAL was given, finite and > 0, so the three arrays above hold values.
  std::array<bool, 5> real_valid{};
};
// `draws[k]` is realization k's ERR; `real` is ERR_REAL (nullptr: no real recording). Throws
// std::invalid_argument when a draw is not finite.
PredictiveStats predictiveStats(const std::vector<DriftStats>& draws, const DriftStats* real);

// Mean over draws, statistic by statistic.
DriftStats meanDriftStats(const std::vector<DriftStats>& draws);

}  // namespace graftnav
