#include "graftnav/sg/evaluate_pipeline.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>

#include "graftnav/sg/grafting.h"

namespace graftnav {

namespace {

// One navigation: the real IMU (strategy empty) or realization k of a strategy, at shift s.
struct Unit {
  std::optional<SgStrategy> strategy;
  int realization = 0;
  int shift = 0;
  bool representative() const { return realization == 0 && shift == 0; }
};

struct UnitResult {
  DriftStats rms, max_rms;
  std::optional<Evaluation> full;  // kept for the representative unit only
  std::vector<std::string> notes;  // the navigator's, kept for the representative unit only
};

std::vector<Unit> makeUnits(bool with_real, const std::vector<SgStrategy>& strategies,
                            int realizations, int shifts) {
  std::vector<Unit> units;
  for (int s = 0; s < shifts; ++s) {
    if (with_real) units.push_back({std::nullopt, 0, s});
    for (SgStrategy g : strategies)
      for (int k = 0; k < realizations; ++k) units.push_back({g, k, s});
  }
  return units;
}

// Mean over shifts of unit results with the same (strategy, realization).
struct Averaged {
  DriftStats rms, max_rms;
};
Averaged averageOverShifts(const std::vector<Unit>& units, const std::vector<UnitResult>& res,
                           const std::optional<SgStrategy>& strategy, int realization) {
  std::vector<DriftStats> rms, mx;
  for (std::size_t i = 0; i < units.size(); ++i) {
    if (units[i].strategy != strategy || units[i].realization != realization) continue;
    rms.push_back(res[i].rms);
    mx.push_back(res[i].max_rms);
  }
  return {meanDriftStats(rms), meanDriftStats(mx)};
}

Evaluation& representativeEvaluation(const std::vector<Unit>& units, std::vector<UnitResult>& res,
                                     const std::optional<SgStrategy>& strategy) {
  for (std::size_t i = 0; i < units.size(); ++i)
    if (units[i].strategy == strategy && units[i].representative()) return *res[i].full;
  throw std::logic_error("no representative unit");
}

bool allFinite(const DriftStats& s) {
  for (double v : asArray(s))
    if (!std::isfinite(v)) return false;
  return true;
}

std::string strategyLabels(const std::vector<SgStrategy>& strategies) {
  std::string out;
  for (std::size_t i = 0; i < strategies.size(); ++i) {
    if (i > 0) out += i + 1 == strategies.size() ? " and " : ", ";
    out += sgLabel(strategies[i]);
  }
  return out;
}

// Runs every unit on `jobs` workers; results land at the unit's index.
template <typename NavigateUnit>
std::vector<UnitResult> navigateAll(const std::vector<Unit>& units,
                                    const NavigateUnit& navigate_unit, int jobs, const SgLogFn& log,
                                    const std::string& tag) {
  std::vector<UnitResult> results(units.size());
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex log_mutex;
  std::exception_ptr failure;
  const std::size_t report_every = std::max<std::size_t>(1, units.size() / 10);
  auto worker = [&]() {
    for (std::size_t i = next++; i < units.size(); i = next++) {
      try {
        results[i] = navigate_unit(units[i]);
      } catch (...) {
        std::lock_guard<std::mutex> lock(log_mutex);
        if (!failure) failure = std::current_exception();
        next = units.size();
        return;
      }
      const std::size_t d = ++done;
      if (d % report_every == 0 || d == units.size()) {
        std::lock_guard<std::mutex> lock(log_mutex);
        log(fmt::format("[{}] navigated {} / {}", tag, d, units.size()));
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
  for (auto& th : threads) th.join();
  if (failure) std::rethrow_exception(failure);
  return results;
}

}  // namespace

void SgEvaluationOptions::validate() const {
  if (realizations < 1)
    throw std::invalid_argument("SgEvaluationOptions.realizations must be >= 1, got " +
                                std::to_string(realizations));
  if (outage_shifts < 1)
    throw std::invalid_argument("SgEvaluationOptions.outage_shifts must be >= 1, got " +
                                std::to_string(outage_shifts));
  if (strategies.empty()) throw std::invalid_argument("SgEvaluationOptions.strategies: empty");
  if (jobs < 0)
    throw std::invalid_argument("SgEvaluationOptions.jobs must be >= 0, got " +
                                std::to_string(jobs));
  evaluation.validate();
}

std::vector<OutageScheduleConfig> shiftedSchedules(const OutageScheduleConfig& schedule,
                                                   int shifts) {
  std::vector<OutageScheduleConfig> out;
  for (int s = 0; s < shifts; ++s) {
    OutageScheduleConfig x = schedule;
    x.start_s += s * schedule.period_s / shifts;
    out.push_back(x);
  }
  return out;
}

SgEvaluationPipeline::SgEvaluationPipeline(const SgEvaluationOptions& options, GraftPlan plan,
                                           SgEvaluationInputs inputs)
    : options_(options), plan_(std::move(plan)), inputs_(std::move(inputs)) {
  options_.validate();
  if (inputs_.reference_imu.empty())
    throw std::invalid_argument(inputs_.case_name + ": the reference IMU series is empty");
  if (options_.outage_shifts > 1 && !inputs_.outages.explicit_windows.empty())
    throw std::invalid_argument(
        "SgEvaluationOptions.outage_shifts > 1 needs a periodic outage schedule; the run config "
        "lists explicit windows (outages.windows)");
  schedules_ = shiftedSchedules(inputs_.outages, options_.outage_shifts);
  t_first_s_ = inputs_.reference_imu.front().t_s - inputs_.reference_imu.front().dt_s;
  t_last_s_ = inputs_.reference_imu.back().t_s;
  for (const auto& s : schedules_) {
    if (buildOutageWindows(s, t_first_s_, t_last_s_).empty()) {
      throw std::runtime_error(fmt::format(
          "no GNSS outage fits in the data of '{}' ({:.1f} s of IMU data) with outages of {:g} s every "
          "{:g} s starting {:g} s after the first epoch and ending {:g} s before the last: nothing to "
          "evaluate (a shorter or earlier outage schedule: the run config's outages: or its overrides)",
          inputs_.case_name, t_last_s_ - t_first_s_, s.length_s, s.period_s, s.start_s,
          s.end_margin_s));
    }
  }
  header_.realizations = options_.realizations;
  header_.outage_shifts = options_.outage_shifts;
  for (const auto& s : schedules_) header_.shift_starts_s.push_back(s.start_s);
  header_.notes = inputs_.notes;

  RealizationOptions ro;
  ro.count = options_.realizations;
  ro.seed = options_.seed;
  ro.vary_segment = options_.start_offset_s < 0.0;
  ro.vary_turn_on_bias = options_.vary_turn_on_bias;
  ro.vary_bias_wander = options_.vary_bias_wander;
  draws_ = drawRealizations(ro, plan_.basic, inputs_.tested_profile, t_last_s_ - t_first_s_);
  if (!ro.vary_segment)
    for (auto& d : draws_) d.start_offset_s = options_.start_offset_s;
  describeRealizations();
  if (!inputs_.has_real)
    header_.notes.push_back(
        "no field/tested_imu.txt: ERR_REAL, DIFF and the verdicts are not available");
}

void SgEvaluationPipeline::describeRealizations() {
  const BasicErrorSignal& b = plan_.basic;
  const int K = options_.realizations;
  const double span = t_last_s_ - t_first_s_;
  header_.static_record_s = b.recordLength_s();
  header_.shared_sample_fraction = sharedSampleFraction(draws_, b);
  header_.notes.push_back(fmt::format(
      "basic error signal: lab static record {:.1f} s for a field test of {:.1f} s, extended by mirrored "
      "tiling; {} realizations start at {} of the tiled record",
      b.recordLength_s(), span, K,
      b.recordLength_s() >= K * span ? "disjoint segments"
                                     : "offsets spread over twice its length"));
  if (!draws_.empty() && draws_.front().surrogate_seed) {
    header_.notes.push_back(
        "the record is shorter than the field test: each realization grafts a phase-randomized "
        "surrogate of it (its mean and spectrum at short periods) whose slower content is drawn from the tested "
        "IMU's noise model (docs/grafting.md)");
  }
  if (header_.shared_sample_fraction > 0.0) {
    header_.notes.push_back(
        fmt::format("{:.0f} % of realization pairs take the same lab sample at the same field time "
                    "(a fixed grafting.start_offset_s): their lab noise is shared",
                    100.0 * header_.shared_sample_fraction));
  }
  if (inputs_.reference_noise_profile) {
    const Eigen::Vector2d f =
        referenceResidualFraction(*inputs_.reference_noise_profile, inputs_.tested_profile);
    header_.notes.push_back(fmt::format(
        "the reference IMU's own white noise, grafted along, is {:.2f} % (gyro) and {:.2f} % (accel) "
        "of the tested IMU's",
        100.0 * f[0], 100.0 * f[1]));
  }
  if (K < 19) {
    header_.notes.push_back(
        fmt::format("{} realizations: the [p05, p95] interval covers about {:.0f} % of "
                    "realizations, not 90 % (use 19 or more)",
                    K, 100.0 * (K - 1) / (K + 1)));
  }
}

ImuSeries SgEvaluationPipeline::graft(SgStrategy strategy, int realization) const {
  if (realization < 0 || realization >= static_cast<int>(draws_.size()))
    throw std::out_of_range(fmt::format("realization {} of {}", realization, draws_.size()));
  return graftSeries(inputs_.reference_imu, plan_, strategy, graftOptionsFor(draws_[realization]));
}

namespace {

// SG entries (one per strategy) and REAL of the report from the unit results.
void summarize(const std::vector<Unit>& units, std::vector<UnitResult>& res,
               const SgEvaluationInputs& in, const SgEvaluationOptions& o,
               SgEvaluationReport* rep) {
  std::optional<SgSolutionErrors> real;
  if (in.has_real) {
    real.emplace();
    real->label = "REAL";
    real->imu_file = in.real_imu_file;
    real->evaluation = std::move(representativeEvaluation(units, res, std::nullopt));
    const Averaged a = averageOverShifts(units, res, std::nullopt, 0);
    real->err_rms = a.rms;
    real->err_max_rms = a.max_rms;
  }
  for (SgStrategy g : o.strategies) {
    SgSolutionErrors e;
    e.label = sgLabel(g);
    e.evaluation = std::move(representativeEvaluation(units, res, g));
    std::vector<DriftStats> mx;
    for (int k = 0; k < o.realizations; ++k) {
      const Averaged a = averageOverShifts(units, res, g, k);
      if (!allFinite(a.rms))
        throw std::runtime_error(
            fmt::format("{} realization {}: an outage statistic is not finite (no evaluated "
                        "epoch inside the outages?)",
                        e.label, k));
      e.draws.push_back(a.rms);
      mx.push_back(a.max_rms);
    }
    e.err_rms = meanDriftStats(e.draws);
    e.err_max_rms = meanDriftStats(mx);
    e.predictive = predictiveStats(e.draws, real ? &real->err_rms : nullptr);
    rep->solutions.push_back(std::move(e));
  }
  if (real) rep->solutions.push_back(std::move(*real));
}

}  // namespace

SgEvaluationReport SgEvaluationPipeline::run(const SolutionReference& reference,
                                             const SgNavigator& navigate,
                                             const std::string& estimator_name,
                                             const SgLogFn& log_in) const {
  const SgLogFn log = log_in ? log_in : [](const std::string&) {};
  const std::string tag = std::filesystem::path(inputs_.case_name).filename().string();
  const std::vector<Unit> units = makeUnits(inputs_.has_real, options_.strategies,
                                            options_.realizations, options_.outage_shifts);
  auto navigate_unit = [&](const Unit& u) {
    std::optional<ImuSeries> grafted;
    if (u.strategy) grafted = graft(*u.strategy, u.realization);
    SgNavigation nav = navigate(std::move(grafted), schedules_[u.shift]);
    UnitResult r;
    Evaluation e =
        evaluateSolution(nav.solution, reference.states, nav.outages, options_.evaluation);
    r.rms = e.outage_rms;
    r.max_rms = e.outage_max_rms;
    if (u.representative()) {
      r.full = std::move(e);
      r.notes = std::move(nav.notes);
    }
    return r;
  };
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int jobs = std::max(
      1, std::min<int>(static_cast<int>(units.size()), options_.jobs > 0 ? options_.jobs : hw));
  log(
      fmt::format("[{}] navigating {} realizations of {}{} with {} at {} outage schedule(s) "
                  "({} navigations, {} in parallel)",
                  tag, options_.realizations, strategyLabels(options_.strategies),
                  inputs_.has_real ? " and REAL" : "", estimator_name, options_.outage_shifts,
                  units.size(), jobs));
  std::vector<UnitResult> results = navigateAll(units, navigate_unit, jobs, log, tag);

  SgEvaluationReport rep = header_;
  rep.estimator = estimator_name;
  rep.reference = reference.description;
  // The first unit (REAL, else the first strategy's realization 0, at the first schedule) says
  // what was assumed.
  for (const auto& s : results.front().notes) rep.notes.push_back(s);
  rep.outages = buildOutageWindows(schedules_.front(), t_first_s_, t_last_s_);
  rep.outage_length_s = rep.outages.front().length_s();
  summarize(units, results, inputs_, options_, &rep);
  return rep;
}

}  // namespace graftnav
