#include "graftnav/eval/cross_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graftnav/eval/evaluation.h"

namespace graftnav {
namespace {

// Indices of the sigma vector (nav_solution.h): position N, E, D; attitude about down.
constexpr int kPosN = 0, kPosE = 1, kPosD = 2, kAttD = 8;

// Sums of one compared quantity over the outage epochs.
struct StatSum {
  double d2 = 0.0, s2 = 0.0, z2 = 0.0, z_max = -1.0, t_max = 0.0;
  int n = 0, n_z = 0;
  void add(double t_s, double d, double var) {
    d2 += d * d;
    ++n;
    if (!(var > 0.0) || !std::isfinite(var)) return;
    const double z = std::abs(d) / std::sqrt(var);
    s2 += var;
    z2 += z * z;
    ++n_z;
    if (z > z_max) {
      z_max = z;
      t_max = t_s;
    }
  }
  CrossCheckStat stat() const {
    CrossCheckStat s;
    s.epochs = n;
    s.normalized_epochs = n_z;
    if (n > 0) s.rms_difference = std::sqrt(d2 / n);
    if (n_z > 0) {
      s.rms_sigma = std::sqrt(s2 / n_z);
      s.rms_normalized = std::sqrt(z2 / n_z);
      s.max_normalized = z_max;
      s.max_normalized_t_s = t_max;
    }
    return s;
  }
};

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
