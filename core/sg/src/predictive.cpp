#include "graftnav/sg/predictive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/sg/sg_statistics.h"

namespace graftnav {

double weibullQuantile(std::vector<double> v, double p) {
  if (v.empty()) throw std::invalid_argument("weibullQuantile: no values");
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("weibullQuantile: p outside [0, 1]");
  for (double x : v)
    if (!std::isfinite(x)) throw std::invalid_argument("weibullQuantile: non-finite value");
  std::sort(v.begin(), v.end());
  const double n = static_cast<double>(v.size());
  const double rank = std::clamp(p * (n + 1.0), 1.0, n);  // 1-based
  const std::size_t lo = static_cast<std::size_t>(std::floor(rank)) - 1;
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  const double w = rank - std::floor(rank);
  return v[lo] + w * (v[hi] - v[lo]);
}

PredictiveSummary summarizeDraws(const std::vector<double>& v) {
  PredictiveSummary s;
  s.p05 = weibullQuantile(v, 0.05);
  s.p50 = weibullQuantile(v, 0.50);
  s.p95 = weibullQuantile(v, 0.95);
  s.count = static_cast<int>(v.size());
  double sum = 0.0;
  for (double x : v) sum += x;
  s.mean = sum / s.count;
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sd = s.count > 1 ? std::sqrt(ss / (s.count - 1)) : 0.0;
  return s;
}

double realPercentile(const std::vector<double>& draws, double real) {
  if (draws.empty()) throw std::invalid_argument("realPercentile: no draws");
  double below = 0.0;
  for (double x : draws) below += x < real ? 1.0 : (x == real ? 0.5 : 0.0);
  return below / static_cast<double>(draws.size());
}

const char* verdictName(Verdict v) {
  switch (v) {
    case Verdict::kOptimistic:
      return "optimistic";
    case Verdict::kPessimistic:
      return "pessimistic";
    case Verdict::kConsistent:
      break;
  }
  return "consistent";
}

Verdict verdictFor(const PredictiveSummary& s, double real) {
  if (real > s.p95) return Verdict::kOptimistic;
  if (real < s.p05) return Verdict::kPessimistic;
  return Verdict::kConsistent;
}

std::array<double, 2> diffInterval(const std::vector<double>& draws, double real) {
  if (!(std::isfinite(real) && real > 0.0)) {
    throw std::invalid_argument("diffInterval: ERR_REAL must be finite and > 0, got " +
                                std::to_string(real));
  }
  std::vector<double> d;
  d.reserve(draws.size());
  for (double x : draws) d.push_back(std::fabs(x - real) / real);
  return {weibullQuantile(d, 0.05), weibullQuantile(d, 0.95)};
}

DriftStats meanDriftStats(const std::vector<DriftStats>& draws) {
  if (draws.empty()) throw std::invalid_argument("meanDriftStats: no draws");
  std::array<double, 5> sum{};
  for (const auto& d : draws) {
    const auto a = asArray(d);
    for (int i = 0; i < 5; ++i) sum[i] += a[i];
  }
  for (double& x : sum) x /= static_cast<double>(draws.size());
  return fromArray(sum);
}

PredictiveStats predictiveStats(const std::vector<DriftStats>& draws, const DriftStats* real) {
  PredictiveStats out;
  for (int i = 0; i < 5; ++i) {
    std::vector<double> v;
    v.reserve(draws.size());
    for (const auto& d : draws) v.push_back(asArray(d)[i]);
    out.summary[i] = summarizeDraws(v);
    if (!real) continue;
    const double r = asArray(*real)[i];
    if (!(std::isfinite(r) && r > 0.0)) continue;
    out.real_valid[i] = true;
    out.real_percentile[i] = realPercentile(v, r);
    out.diff_interval[i] = diffInterval(v, r);
    out.verdict[i] = verdictFor(out.summary[i], r);
  }
  return out;
}

}  // namespace graftnav
