#include "graftnav/eval/spooled_comparison.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <utility>

#include "cross_check_sums.h"
#include "graftnav/eval/streamed_evaluation.h"

namespace graftnav {
namespace {

using cross_check_detail::kAttD;
using cross_check_detail::kPosD;
using cross_check_detail::kPosE;
using cross_check_detail::kPosN;
using cross_check_detail::StatSum;

// sigma^2 of b at times that do not decrease, linear in time between its neighbouring epochs:
// b read forward as far as the time asks (the in-memory form's lower_bound, clamped to the ends).
class VarianceTrack {
 public:
  explicit VarianceTrack(const SolutionSpool& b) : states_(b.states()()), sigmas_(b.sigmas()) {
    has_hi_ = readNext(&hi_t_, &hi_v_);
  }
  PvaSigma at(double t_s) {
    while (hi_t_ < t_s) {
      double t;
      PvaSigma v;
      if (!readNext(&t, &v)) break;
      lo_t_ = hi_t_;
      lo_v_ = hi_v_;
      has_lo_ = true;
      hi_t_ = t;
      hi_v_ = v;
    }
    const bool use_lo = has_lo_ && hi_t_ > t_s;
    const double t_lo = use_lo ? lo_t_ : hi_t_;
    const PvaSigma& v_lo = use_lo ? lo_v_ : hi_v_;
    const double span = hi_t_ - t_lo;
    const double u = span > 0.0 ? std::clamp((t_s - t_lo) / span, 0.0, 1.0) : 0.0;
    return (1.0 - u) * v_lo + u * hi_v_;
  }
  bool empty() const { return !has_hi_; }

 private:
  bool readNext(double* t_s, PvaSigma* var) {
    NavState s;
    PvaSigma sigma;
    if (!states_->next(&s) || !sigmas_.next(&sigma)) return false;
    *t_s = s.t_s;
    *var = sigma.cwiseAbs2();
    return true;
  }
  std::unique_ptr<NavSource> states_;
  SolutionSpool::SigmaPass sigmas_;
  bool has_hi_ = false, has_lo_ = false;
  double hi_t_ = 0.0, lo_t_ = 0.0;
  PvaSigma hi_v_, lo_v_;
};

// Calls `fn` with each evaluated epoch.
class CallbackSink final : public EpochErrorSink {
 public:
  explicit CallbackSink(std::function<void(const EpochError&)> fn) : fn_(std::move(fn)) {}
  void add(const EpochError& e) override { fn_(e); }

 private:
  std::function<void(const EpochError&)> fn_;
};

}  // namespace

Evaluation evaluatePair(const SolutionSpool& a, const SolutionSpool& b,
                        const std::vector<TimeWindow>& outages) {
  StreamedEvaluation ev(b.states()(), outages, EvaluationOptions{}, "a");
  const std::unique_ptr<NavSource> states = a.states()();
  NavState s;
  while (states->next(&s)) ev.add(s, nullptr);
  return ev.finish();
}

CrossCheck crossCheck(const SolutionSpool& a, const SolutionSpool& b,
                      const std::vector<TimeWindow>& outages, DifferenceCovariance form) {
  CrossCheck out;
  out.form = form;
  out.has_sigma = a.hasSigma() && b.hasSigma();
  const double sign = form == DifferenceCovariance::kFilterSmoother ? -1.0 : 1.0;
  StatSum h, v, y;
  // a's sigma at the epochs added and not yet evaluated (the join lags by a few epochs).
  std::deque<std::pair<double, PvaSigma>> pending;
  std::unique_ptr<VarianceTrack> b_var;
  if (out.has_sigma) b_var = std::make_unique<VarianceTrack>(b);
  const auto on_epoch = [&](const EpochError& e) {
    while (!pending.empty() && pending.front().first < e.t_s) pending.pop_front();
    if (e.outage < 0) return;
    PvaSigma var = PvaSigma::Constant(std::nan(""));
    if (out.has_sigma) var = pending.front().second.cwiseAbs2() + sign * b_var->at(e.t_s);
    h.add(e.t_s, e.pos_ned_m.head<2>().norm(), var[kPosN] + var[kPosE]);
    v.add(e.t_s, e.pos_ned_m.z(), var[kPosD]);
    y.add(e.t_s, e.att_n_rad.z(), var[kAttD]);
  };
  EvaluationOptions o;
  o.epochs = EvaluationEpochs::kSolution;
  StreamedEvaluation ev(b.states()(), outages, o, "a", ExpectedRates{},
                        [&]() { return std::make_unique<CallbackSink>(on_epoch); });
  const std::unique_ptr<NavSource> states = a.states()();
  std::optional<SolutionSpool::SigmaPass> sigmas;
  if (out.has_sigma) sigmas.emplace(a.sigmas());
  NavState s;
  PvaSigma sigma = PvaSigma::Constant(std::nan(""));
  while (states->next(&s)) {
    if (sigmas) sigmas->next(&sigma);
    pending.emplace_back(s.t_s, sigma);
    ev.add(s, nullptr);
  }
  ev.finish();
  out.horizontal = h.stat();
  out.vertical = v.stat();
  out.heading = y.stat();
  return out;
}

}  // namespace graftnav
