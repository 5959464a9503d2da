#include "graftnav/sg/evaluate_pipeline.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "graftnav/parallel/worker_pool.h"
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
  std::optional<Evaluation> full;  // kept for the representative unit only (epochs when held)
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

// The work of one worker at a time: REAL at one schedule, or realization k at every strategy and
// schedule (they share the realization's error signal, made once).
struct Task {
  std::optional<int> realization;  // empty: REAL
  std::vector<std::size_t> units;  // indices into the units
};

std::vector<Task> makeTasks(const std::vector<Unit>& units) {
  std::vector<Task> tasks;
  std::vector<std::size_t> of_realization;  // task index of realization k, or npos
  for (std::size_t i = 0; i < units.size(); ++i) {
    const Unit& u = units[i];
    if (!u.strategy) {
      tasks.push_back({std::nullopt, {i}});
      continue;
    }
    const auto k = static_cast<std::size_t>(u.realization);
    if (k >= of_realization.size()) of_realization.resize(k + 1, std::string::npos);
    if (of_realization[k] == std::string::npos) {
      of_realization[k] = tasks.size();
      tasks.push_back({u.realization, {}});
    }
    tasks[of_realization[k]].units.push_back(i);
  }
  return tasks;
}

// Keeps a representative unit's epochs in its Evaluation (when no sink is given for them).
class KeepEpochs final : public EpochErrorSink {
 public:
  explicit KeepEpochs(std::vector<EpochError>* kept) : kept_(kept) {}
  void add(const EpochError& e) override { epochs_.push_back(e); }
  void commit() override { *kept_ = std::move(epochs_); }

 private:
  std::vector<EpochError>* kept_;
  std::vector<EpochError> epochs_;
};

// A grafted realization as a recording: each block of the reference IMU grafted as it is read.
ImuRecording graftedRecordingOf(const ImuRecording& ref, std::shared_ptr<const GraftSignal> sig,
                                const GraftPlan& plan, SgStrategy strategy) {
  const double t0 = ref.beginTime_s();
  const SensorDynamicFit* gyro = strategy == SgStrategy::kFull ? &plan.gyro_fit : nullptr;
  const SensorDynamicFit* accel = strategy == SgStrategy::kFull ? &plan.accel_fit : nullptr;
  ImuRecording r;
  ImuSeries one;
  sig->graft({ref.first}, t0, gyro, accel, &one);
  r.first = one.front();
  sig->graft({ref.last}, t0, gyro, accel, &one);
  r.last = one.front();
  r.samples = ref.samples;
  r.pass = [ref_pass = ref.pass, sig, t0, gyro, accel](const ImuBlockFn& block) {
    ImuSeries out;
    ref_pass([&](const ImuSeries& b) {
      sig->graft(b, t0, gyro, accel, &out);
      block(out);
    });
  };
  return r;
}

// The held navigator as a streamed one: the grafted recording is collected into a series, and
// the returned solution's epochs are handed on.
SgStreamNavigator streamedFromHeld(const SgNavigator& held) {
  return [&held](const SgImu& imu, const OutageScheduleConfig& schedule, const SgStartFn& start) {
    std::optional<ImuSeries> grafted;
    if (imu.strategy) grafted = collectRecording(imu.imu);
    SgNavigation nav = held(std::move(grafted), schedule);
    NavSolution& sol = nav.solution;
    const double rate = sol.states.size() > 1 ? (sol.states.size() - 1) /
                                                    (sol.states.back().t_s - sol.states.front().t_s)
                                              : 0.0;
    const SgEpochFn epochs = start(nav.outages, rate);
    const bool has_sigma = sol.sigma.size() == sol.states.size();
    for (std::size_t i = 0; i < sol.states.size(); ++i)
      epochs(sol.states[i], has_sigma ? &sol.sigma[i] : nullptr);
    NavSolution book;  // the epochs are not kept
    book.copyBookkeeping(sol);
    sol = std::move(book);
    return nav;
  };
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
  if (!inputs_.reference_recording.pass) {
    if (inputs_.reference_imu.empty())
      throw std::invalid_argument(inputs_.case_name + ": the reference IMU series is empty");
    inputs_.reference_recording = heldRecording(std::move(inputs_.reference_imu));
    inputs_.reference_imu = {};
  }
  inputs_.has_real = inputs_.has_real || inputs_.real_recording.has_value();
  if (options_.outage_shifts > 1 && !inputs_.outages.explicit_windows.empty())
    throw std::invalid_argument(
        "SgEvaluationOptions.outage_shifts > 1 needs a periodic outage schedule; the run config "
        "lists explicit windows (outages.windows)");
  schedules_ = shiftedSchedules(inputs_.outages, options_.outage_shifts);
  t_first_s_ = inputs_.reference_recording.beginTime_s();
  t_last_s_ = inputs_.reference_recording.last.t_s;
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

GraftOptions SgEvaluationPipeline::graftOptions(int realization) const {
  GraftOptions g = graftOptionsFor(draws_[static_cast<std::size_t>(realization)]);
  g.spool_surrogate = options_.spool_surrogates;
  return g;
}

ImuRecording SgEvaluationPipeline::graftedRecording(SgStrategy strategy, int realization) const {
  if (realization < 0 || realization >= static_cast<int>(draws_.size()))
    throw std::out_of_range(fmt::format("realization {} of {}", realization, draws_.size()));
  auto sig = std::make_shared<const GraftSignal>(plan_.basic, graftOptions(realization));
  return graftedRecordingOf(inputs_.reference_recording, std::move(sig), plan_, strategy);
}

ImuSeries SgEvaluationPipeline::graft(SgStrategy strategy, int realization) const {
  return collectRecording(graftedRecording(strategy, realization));
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

// One run's navigations: each unit navigated and evaluated against SOL_REF as its epochs come.
struct SgEvaluationPipeline::Work {
  const SgEvaluationPipeline& p;
  const SolutionReference& reference;
  const SgStreamNavigator& navigate;
  const SgRunHooks& hooks;
  const std::string& estimator;
  mutable std::mutex signal_mutex{};  // initialized here: Work is built as an aggregate without it

  std::unique_ptr<NavSource> openReference() const {
    return reference.open ? reference.open() : seriesNavSource(reference.states);
  }

  UnitResult unit(const Unit& u, const SgImu& imu) const {
    UnitResult r;
    std::vector<EpochError> kept;
    EpochSinkFactory sinks;
    if (u.representative()) {
      const std::string label = u.strategy ? sgLabel(*u.strategy) : "REAL";
      sinks = [this, label, &kept]() -> std::unique_ptr<EpochErrorSink> {
        if (hooks.epoch_sink) return hooks.epoch_sink(label);
        return std::make_unique<KeepEpochs>(&kept);
      };
    }
    std::optional<StreamedEvaluation> ev;
    const SgStartFn start = [&](const std::vector<TimeWindow>& outages, double rate_hz) {
      if (ev) throw std::logic_error("SgStreamNavigator: start called twice");
      ev.emplace(openReference(), outages, p.options_.evaluation, estimator,
                 ExpectedRates{rate_hz, reference.rate_hz}, sinks);
      return SgEpochFn([&ev](const NavState& s, const PvaSigma* sg) { ev->add(s, sg); });
    };
    SgNavigation nav = navigate(imu, p.schedules_[static_cast<std::size_t>(u.shift)], start);
    if (!ev) throw std::logic_error("SgStreamNavigator: returned without starting");
    Evaluation e = ev->finish();
    ev->commitEpochs();
    r.rms = e.outage_rms;
    r.max_rms = e.outage_max_rms;
    if (u.representative()) {
      e.epochs = std::move(kept);
      r.full = std::move(e);
      r.notes = std::move(nav.notes);
    }
    return r;
  }

  // Every unit of a task; a realization's signal is made once for all of them.
  void task(const Task& t, const std::vector<Unit>& units, std::vector<UnitResult>& results,
            const std::function<void()>& done) const {
    std::shared_ptr<const GraftSignal> sig;
    if (t.realization) {
      // One realization's signal is made at a time: a surrogate's transforms are the largest
      // transient of the run (several arrays of twice the lab record's samples).
      std::lock_guard<std::mutex> lock(signal_mutex);
      sig = std::make_shared<const GraftSignal>(p.plan_.basic, p.graftOptions(*t.realization));
    }
    for (std::size_t i : t.units) {
      const Unit& u = units[i];
      SgImu imu;
      imu.strategy = u.strategy;
      imu.realization = u.realization;
      if (u.strategy) {
        imu.imu = graftedRecordingOf(p.inputs_.reference_recording, sig, p.plan_, *u.strategy);
      } else if (p.inputs_.real_recording) {
        imu.imu = *p.inputs_.real_recording;
      }
      results[i] = unit(u, imu);
      done();
    }
  }
};

SgEvaluationReport SgEvaluationPipeline::run(const SolutionReference& reference,
                                             const SgStreamNavigator& navigate,
                                             const std::string& estimator_name,
                                             const SgRunHooks& hooks) const {
  const SgLogFn log = hooks.log ? hooks.log : [](const std::string&) {};
  const std::string tag = std::filesystem::path(inputs_.case_name).filename().string();
  const std::vector<Unit> units = makeUnits(inputs_.has_real, options_.strategies,
                                            options_.realizations, options_.outage_shifts);
  const std::vector<Task> tasks = makeTasks(units);
  const int jobs = workerCount(tasks.size(), options_.jobs);
  log(
      fmt::format("[{}] navigating {} realizations of {}{} with {} at {} outage schedule(s) "
                  "({} navigations, {} in parallel)",
                  tag, options_.realizations, strategyLabels(options_.strategies),
                  inputs_.has_real ? " and REAL" : "", estimator_name, options_.outage_shifts,
                  units.size(), jobs));
  std::vector<UnitResult> results(units.size());
  std::atomic<std::size_t> done{0};
  std::mutex log_mutex;
  const std::size_t report_every = std::max<std::size_t>(1, units.size() / 10);
  const std::function<void()> one_done = [&]() {
    const std::size_t d = ++done;
    if (d % report_every == 0 || d == units.size()) {
      std::lock_guard<std::mutex> lock(log_mutex);
      log(fmt::format("[{}] navigated {} / {}", tag, d, units.size()));
    }
  };
  const Work work{*this, reference, navigate, hooks, estimator_name};
  parallelFor(tasks.size(), jobs,
              [&](std::size_t i) { work.task(tasks[i], units, results, one_done); });

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

SgEvaluationReport SgEvaluationPipeline::run(const SolutionReference& reference,
                                             const SgNavigator& navigate,
                                             const std::string& estimator_name,
                                             const SgLogFn& log) const {
  return run(reference, streamedFromHeld(navigate), estimator_name, SgRunHooks{log, {}});
}

}  // namespace graftnav
