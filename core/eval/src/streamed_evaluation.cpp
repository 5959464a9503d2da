#include "graftnav/eval/streamed_evaluation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "evaluation_accumulator.h"
#include "series_window.h"

namespace graftnav {

using eval_detail::EvaluationAccumulator;
using eval_detail::SeriesWindow;
using eval_detail::WindowInterpolator;

namespace {

// One set of evaluated epochs (the solution's or the reference's) with its statistics and sink.
struct EpochSet {
  EpochSet(const std::vector<TimeWindow>& windows, const EvaluationOptions& options,
           std::unique_ptr<EpochErrorSink> s)
      : sink(std::move(s)), acc(windows, options, &ev, [this](const EpochError& e) {
          if (sink) sink->add(e);
        }) {}
  Evaluation ev;
  std::unique_ptr<EpochErrorSink> sink;
  EvaluationAccumulator acc;
};

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

}  // namespace

struct StreamedEvaluation::Impl {
  Impl(std::unique_ptr<NavSource> r, const std::vector<TimeWindow>& outages,
       const EvaluationOptions& o, std::string n)
      : reference(std::move(r)),
        windows(eval_detail::sortedWindows(outages)),
        options(o),
        name(std::move(n)) {}

  bool pullReference();
  void addAtSolution(const NavState& s, const PvaSigma* sigma);
  void advanceAtReference();
  void evaluateAtReference(const NavState& r);
  void trim();
  void checkSigma(const PvaSigma* sigma);
  EpochSet* chosenSet();

  std::unique_ptr<NavSource> reference;
  const std::vector<TimeWindow> windows;
  const EvaluationOptions options;
  const std::string name;
  SeriesWindow ref, sol;
  WindowInterpolator ref_at{ref}, sol_at{sol};
  std::optional<EpochSet> at_solution, at_reference;
  std::size_t next_ref = 0;  // at_reference: the next reference epoch to evaluate
  std::size_t k = 0;         // at_reference: the solution epoch at or before it (sigma bracket)
  int with_sigma = -1;       // -1 not known yet, 0 no epoch has a sigma, 1 every epoch has one
  bool finished = false;
  EpochSet* kept = nullptr;
};

bool StreamedEvaluation::Impl::pullReference() {
  if (ref.ended()) return false;
  NavState s;
  if (reference->next(&s)) {
    ref.push(s, nullptr, "reference");
    return true;
  }
  ref.end();
  return false;
}

void StreamedEvaluation::Impl::addAtSolution(const NavState& s, const PvaSigma* sigma) {
  while (!ref_at.ready(s.t_s)) pullReference();
  const std::optional<NavState> r = ref_at.at(s.t_s);
  if (r) at_solution->acc.add(s, sigma, *r);
}

// evaluateSolution's loop over the reference epochs, each as soon as the solution reaches past it.
void StreamedEvaluation::Impl::advanceAtReference() {
  for (;;) {
    if (!ref.has(next_ref)) {
      if (!pullReference()) return;
      continue;
    }
    const NavState r = ref.at(next_ref).state;
    if (!sol_at.ready(r.t_s)) return;
    evaluateAtReference(r);
    ++next_ref;
  }
}

void StreamedEvaluation::Impl::evaluateAtReference(const NavState& r) {
  const std::optional<NavState> s = sol_at.at(r.t_s);
  if (!s) return;
  if (with_sigma != 1) {
    at_reference->acc.add(*s, nullptr, r);
    return;
  }
  // The window holds a solution epoch after r (or the solution ended): the bracket is in it.
  while (sol.has(k + 1) && sol.at(k + 1).state.t_s <= r.t_s) ++k;
  const std::size_t k1 = sol.has(k + 1) ? k + 1 : k;
  const NavState& a = sol.at(k).state;
  const double span = sol.at(k1).state.t_s - a.t_s;
  const double u = span > 0 ? std::clamp((r.t_s - a.t_s) / span, 0.0, 1.0) : 0.0;
  const PvaSigma sg = (1.0 - u) * sol.at(k).sigma + u * sol.at(k1).sigma;
  at_reference->acc.add(*s, &sg, r);
}

void StreamedEvaluation::Impl::trim() {
  std::size_t need_ref = ref.count(), need_sol = sol.count();
  if (at_solution) need_ref = std::min(need_ref, ref_at.index());
  if (at_reference) {
    need_ref = std::min(need_ref, next_ref);
    // k (the sigma bracket) moves only when the solution has sigmas; once the reference has
    // ended and every epoch of it is evaluated, no solution epoch is needed any more.
    need_sol = with_sigma == 1 ? std::min(sol_at.index(), k) : sol_at.index();
    if (ref.ended() && next_ref >= ref.count()) need_sol = sol.count();
  }
  ref.trimBefore(need_ref);
  sol.trimBefore(need_sol);
}

void StreamedEvaluation::Impl::checkSigma(const PvaSigma* sigma) {
  const int has = sigma ? 1 : 0;
  if (with_sigma < 0) with_sigma = has;
  if (with_sigma != has)
    throw std::invalid_argument(
        fmt::format("evaluation of '{}': solution epoch {} {} a sigma and the first did {}", name,
                    sol.count(), has ? "has" : "has no", has ? "not" : "have one"));
}

EpochSet* StreamedEvaluation::Impl::chosenSet() {
  const double sol_rate = eval_detail::seriesRate(sol.count(), sol.first().t_s, sol.last().t_s);
  const double ref_rate = eval_detail::seriesRate(ref.count(), ref.first().t_s, ref.last().t_s);
  const bool at_ref = options.epochs == EvaluationEpochs::kReference ||
                      (options.epochs == EvaluationEpochs::kAuto && ref_rate < sol_rate);
  EpochSet* set =
      at_ref ? (at_reference ? &*at_reference : nullptr) : (at_solution ? &*at_solution : nullptr);
  if (!set)
    throw std::logic_error(fmt::format(
        "evaluation of '{}': the expected rates chose the {} epochs, but the series' rates "
        "(solution {:.6g} Hz, reference {:.6g} Hz) choose the other",
        name, at_ref ? "solution's" : "reference's", sol_rate, ref_rate));
  return set;
}

StreamedEvaluation::StreamedEvaluation(std::unique_ptr<NavSource> reference,
                                       const std::vector<TimeWindow>& outages,
                                       const EvaluationOptions& options, std::string solution_name,
                                       const ExpectedRates& expected,
                                       const EpochSinkFactory& make_sink) {
  options.validate();
  if (!reference) throw std::invalid_argument("StreamedEvaluation: no reference");
  impl_ = std::make_unique<Impl>(std::move(reference), outages, options, std::move(solution_name));
  bool at_solution = options.epochs != EvaluationEpochs::kReference;
  bool at_reference = options.epochs != EvaluationEpochs::kSolution;
  if (options.epochs == EvaluationEpochs::kAuto && expected.solution_hz > 0.0 &&
      expected.reference_hz > 0.0) {
    const double ratio = expected.reference_hz / expected.solution_hz;
    if (ratio >= kDecisiveRateRatio) at_reference = false;       // the reference is denser
    if (ratio <= 1.0 / kDecisiveRateRatio) at_solution = false;  // the solution is denser
  }
  auto sink = [&]() { return make_sink ? make_sink() : nullptr; };
  if (at_solution) impl_->at_solution.emplace(impl_->windows, impl_->options, sink());
  if (at_reference) impl_->at_reference.emplace(impl_->windows, impl_->options, sink());
}

StreamedEvaluation::~StreamedEvaluation() = default;

int StreamedEvaluation::epochSets() const {
  return (impl_->at_solution ? 1 : 0) + (impl_->at_reference ? 1 : 0);
}

std::size_t StreamedEvaluation::heldEpochs() const { return impl_->ref.held() + impl_->sol.held(); }

void StreamedEvaluation::add(const NavState& state, const PvaSigma* sigma) {
  Impl& m = *impl_;
  if (m.finished) throw std::logic_error("StreamedEvaluation::add after finish");
  if (!std::isfinite(state.t_s))
    throw std::invalid_argument(fmt::format("evaluation of '{}': solution epoch {} has time {}",
                                            m.name, m.sol.count(), state.t_s));
  m.checkSigma(sigma);
  m.sol.push(state, sigma, "solution");
  if (m.at_solution) m.addAtSolution(state, sigma);
  if (m.at_reference) m.advanceAtReference();
  m.trim();
}

Evaluation StreamedEvaluation::finish() {
  Impl& m = *impl_;
  if (m.finished) throw std::logic_error("StreamedEvaluation::finish called twice");
  m.finished = true;
  m.sol.end();
  if (m.at_reference) m.advanceAtReference();
  while (m.pullReference()) m.ref.trimBefore(m.ref.count());  // its count and last epoch
  if (m.sol.empty() || m.ref.empty() || m.sol.last().t_s < m.ref.first().t_s ||
      m.sol.first().t_s > m.ref.last().t_s) {
    throw std::invalid_argument("evaluateSolution: solution '" + m.name +
                                "' and the reference do not overlap in time");
  }
  EpochSet* set = m.chosenSet();
  if (set->ev.epoch_count == 0) {
    throw std::invalid_argument("evaluateSolution: no solution epoch of '" + m.name +
                                "' lies inside the reference span");
  }
  set->acc.finish();
  Evaluation ev = std::move(set->ev);
  // The other set's sink is dropped uncommitted.
  if (set == (m.at_solution ? &*m.at_solution : nullptr)) {
    if (m.at_reference) m.at_reference->sink.reset();
  } else if (m.at_solution) {
    m.at_solution->sink.reset();
  }
  m.kept = set;
  return ev;
}

void StreamedEvaluation::commitEpochs() {
  Impl& m = *impl_;
  if (!m.kept) throw std::logic_error("StreamedEvaluation::commitEpochs before finish");
  if (m.kept->sink) m.kept->sink->commit();
}

Evaluation evaluateSolutionStreamed(const NavSolution& solution, const NavOpenFn& reference,
                                    const std::vector<TimeWindow>& outages,
                                    const EvaluationOptions& options,
                                    const EpochSinkFactory& make_sink) {
  StreamedEvaluation se(reference(), outages, options, solution.estimator, {}, make_sink);
  const bool has_sigma = solution.sigma.size() == solution.states.size();
  for (std::size_t i = 0; i < solution.states.size(); ++i)
    se.add(solution.states[i], has_sigma ? &solution.sigma[i] : nullptr);
  Evaluation ev = se.finish();
  se.commitEpochs();
  return ev;
}

}  // namespace graftnav
