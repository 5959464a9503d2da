#include "graftnav/eval/cross_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cross_check_sums.h"
#include "graftnav/eval/evaluation.h"

namespace graftnav {
namespace {

using cross_check_detail::kAttD;
using cross_check_detail::kPosD;
using cross_check_detail::kPosE;
using cross_check_detail::kPosN;
using cross_check_detail::StatSum;

// sigma^2 of b at time t, linear in time between its neighbouring epochs.
PvaSigma varianceAt(const NavSolution& b, double t_s) {
  const NavSeries& s = b.states;
  auto it = std::lower_bound(s.begin(), s.end(), t_s,
                             [](const NavState& x, double t) { return x.t_s < t; });
  const std::size_t hi = std::min<std::size_t>(it - s.begin(), s.size() - 1);
  const std::size_t lo = hi > 0 && s[hi].t_s > t_s ? hi - 1 : hi;
  const double span = s[hi].t_s - s[lo].t_s;
  const double u = span > 0.0 ? std::clamp((t_s - s[lo].t_s) / span, 0.0, 1.0) : 0.0;
  const PvaSigma v_lo = b.sigma[lo].cwiseAbs2(), v_hi = b.sigma[hi].cwiseAbs2();
  return (1.0 - u) * v_lo + u * v_hi;
}

std::size_t indexAt(const NavSolution& a, double t_s) {
  auto it = std::lower_bound(a.states.begin(), a.states.end(), t_s,
                             [](const NavState& x, double t) { return x.t_s < t; });
  return std::min<std::size_t>(it - a.states.begin(), a.states.size() - 1);
}

}  // namespace

const char* differenceCovarianceName(DifferenceCovariance form) {
  return form == DifferenceCovariance::kFilterSmoother ? "filter-smoother" : "sum-upper-bound";
}

double CrossCheck::maxNormalized() const {
  double m = CrossCheckStat::kNaN;
  for (const CrossCheckStat* s : {&horizontal, &vertical, &heading})
    if (std::isfinite(s->max_normalized) && !(m >= s->max_normalized)) m = s->max_normalized;
  return m;
}

CrossCheck crossCheck(const NavSolution& a, const NavSolution& b,
                      const std::vector<TimeWindow>& outages, DifferenceCovariance form) {
  EvaluationOptions o;
  o.epochs = EvaluationEpochs::kSolution;
  const Evaluation ev = evaluateSolution(a, b.states, outages, o);
  CrossCheck out;
  out.form = form;
  out.has_sigma = a.sigma.size() == a.states.size() && b.sigma.size() == b.states.size() &&
                  !a.states.empty() && !b.states.empty();
  const double sign = form == DifferenceCovariance::kFilterSmoother ? -1.0 : 1.0;
  StatSum h, v, y;
  for (const EpochError& e : ev.epochs) {
    if (e.outage < 0) continue;
    PvaSigma var = PvaSigma::Constant(std::nan(""));
    if (out.has_sigma) var = a.sigma[indexAt(a, e.t_s)].cwiseAbs2() + sign * varianceAt(b, e.t_s);
    h.add(e.t_s, e.pos_ned_m.head<2>().norm(), var[kPosN] + var[kPosE]);
    v.add(e.t_s, e.pos_ned_m.z(), var[kPosD]);
    y.add(e.t_s, e.att_n_rad.z(), var[kAttD]);
  }
  out.horizontal = h.stat();
  out.vertical = v.stat();
  out.heading = y.stat();
  return out;
}

}  // namespace graftnav
