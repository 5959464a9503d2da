#include "sg_evaluate.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "case_loader.h"
#include "estimators.h"
#include "input_checks.h"
#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/sg/graft_case.h"
#include "graftnav/sg/predictive.h"
#include "graftnav/sg/realization.h"
#include "report_io.h"
#include "script_locator.h"

namespace graftnav::app {
namespace fs = std::filesystem;

namespace {

// Everything loaded once and shared read-only by the navigation workers.
struct Setup {
  CaseInputs c;
  RunConfig rc;
  std::vector<OutageScheduleConfig> schedules;  // one per outage shift
  ImuSelection ref;                             // the reference field IMU (grafted onto)
  std::optional<ImuSelection> real;             // the real tested IMU, when recorded
  std::optional<GraftPlan> plan;
  std::vector<RealizationDraw> draws;
  NavSeries sol_ref;
};

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
  std::vector<std::string> notes;  // makeProblem's, kept for the representative unit only
};

// What checkEvaluationInputs (input_checks.h) does not: the realization options.
void validateOptions(const SgEvaluateOptions& o, const RunConfig& rc) {
  if (o.realizations && *o.realizations < 1)
    throw std::invalid_argument("--realizations must be >= 1, got " + std::to_string(*o.realizations));
  if (o.outage_shifts && *o.outage_shifts < 1)
    throw std::invalid_argument("--outage-shifts must be >= 1, got " + std::to_string(*o.outage_shifts));
  // The estimator and the outage values are checked with the case by checkEvaluationInputs.
  if (o.outage_shifts.value_or(rc.grafting.outage_shifts) > 1 && !rc.outages.explicit_windows.empty())
    throw std::invalid_argument("--outage-shifts needs a periodic schedule; the run config lists explicit windows");
}

// The N schedules: the periodic schedule with its first start moved by s * period / N.
std::vector<OutageScheduleConfig> shiftedSchedules(OutageScheduleConfig oc, int shifts) {
  std::vector<OutageScheduleConfig> out;
  for (int s = 0; s < shifts; ++s) {
    OutageScheduleConfig x = oc;
    x.start_s += s * oc.period_s / shifts;
    out.push_back(x);
  }
  return out;
}

NavSeries solutionReference(const SgEvaluateOptions& o, const Setup& st, SgEvaluationReport* rep,
                            const LogFn& log, const std::string& tag) {
  const CaseInputs& c = st.c;
  if (o.sol_ref == "auto" && !c.reference.empty()) {
    rep->reference = c.reference_is_truth ? "truth (" + c.reference_name + ")"
                                          : "external reference solution (" + c.reference_name + ")";
    return c.reference;
  }
  if (!st.ref.profile_given)
    throw std::runtime_error(c.paths().caseYaml() + ": reference_imu needs noise parameters to smooth SOL_REF");
  log(fmt::format("[{}] smoothing SOL_REF (rts) from the reference IMU and all GNSS", tag));
  std::vector<std::string> n;
  const EstimationProblem pr = makeProblem(c, st.ref, st.rc, std::nullopt, &n);
  rep->reference = "RTS-smoothed reference IMU with all GNSS (SOL_REF of the seed)";
  return runEstimator("rts", pr, st.rc).states;
}

UnitResult navigateUnit(const Unit& u, const Setup& st, const std::string& estimator) {
  ImuSelection sel;
  if (u.strategy) {
    sel.imu = graftSeries(st.ref.imu, *st.plan, *u.strategy, graftOptionsFor(st.draws[u.realization]));
    sel.profile = *st.c.config.tested_imu;
    sel.profile_given = true;
    sel.label = sgLabel(*u.strategy);
  } else {
    sel = *st.real;
  }
  UnitResult r;
  EstimationProblem pr = makeProblem(st.c, sel, st.rc, st.schedules[u.shift], &r.notes);
  sel = ImuSelection();  // one IMU series per worker: the problem holds its own copy
  const NavSolution sol = runEstimator(estimator, pr, st.rc);
  const std::vector<TimeWindow> outages = pr.outages;
  pr = EstimationProblem();
  Evaluation e = evaluateSolution(sol, st.sol_ref, outages, st.rc.evaluation.options);
  r.rms = e.outage_rms;
  r.max_rms = e.outage_max_rms;
  if (u.representative()) r.full = std::move(e);
  else r.notes.clear();
  return r;
}

}  // namespace

namespace {

// Runs every unit on `jobs` workers; results land at the unit's index, so the outcome does not
// depend on the thread schedule.
std::vector<UnitResult> navigateAll(const std::vector<Unit>& units, const Setup& st, const std::string& estimator,
                                    int jobs, const LogFn& log, const std::string& tag) {
  std::vector<UnitResult> results(units.size());
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex log_mutex;
  std::exception_ptr failure;
  const std::size_t report_every = std::max<std::size_t>(1, units.size() / 10);
  auto worker = [&]() {
    for (std::size_t i = next++; i < units.size(); i = next++) {
      try {
        results[i] = navigateUnit(units[i], st, estimator);
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

std::vector<Unit> makeUnits(bool with_real, int realizations, int shifts) {
  std::vector<Unit> units;
  for (int s = 0; s < shifts; ++s) {
    if (with_real) units.push_back({std::nullopt, 0, s});
    for (SgStrategy g : {SgStrategy::kBasic, SgStrategy::kFull})
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

const Evaluation& representativeEvaluation(const std::vector<Unit>& units, std::vector<UnitResult>& res,
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

// SG1, SG2 (and REAL) entries of the report from the unit results.
void summarize(const std::vector<Unit>& units, std::vector<UnitResult>& res, const Setup& st, int K,
               const SgEvaluateOptions& o, SgEvaluationReport* rep) {
  std::optional<SgSolutionErrors> real;
  if (st.real) {
    real.emplace();
    real->label = "REAL";
    real->imu_file = st.real->path;
    real->evaluation = representativeEvaluation(units, res, std::nullopt);
    const Averaged a = averageOverShifts(units, res, std::nullopt, 0);
    real->err_rms = a.rms;
    real->err_max_rms = a.max_rms;
  }
  for (SgStrategy g : {SgStrategy::kBasic, SgStrategy::kFull}) {
    SgSolutionErrors e;
    e.label = sgLabel(g);
    e.imu_file = (fs::path(o.out_dir) / ("IMU_" + e.label + ".txt")).string();
    e.evaluation = representativeEvaluation(units, res, g);
    std::vector<DriftStats> mx;
    for (int k = 0; k < K; ++k) {
      const Averaged a = averageOverShifts(units, res, g, k);
      if (!allFinite(a.rms))
        throw std::runtime_error(fmt::format("{} realization {}: an outage statistic is not finite (no evaluated epoch inside the outages?)", e.label, k));
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

namespace {

void describeRealizations(const Setup& st, int K, SgEvaluationReport* rep) {
  const BasicErrorSignal& b = st.plan->basic;
  const double span = st.ref.imu.back().t_s - (st.ref.imu.front().t_s - st.ref.imu.front().dt_s);
  rep->static_record_s = b.recordLength_s();
  rep->shared_sample_fraction = sharedSampleFraction(st.draws, b);
  rep->notes.push_back(fmt::format(
      "basic error signal: lab static record {:.1f} s for a field test of {:.1f} s, extended by mirrored "
      "tiling; {} realizations start at {} of the tiled record",
      b.recordLength_s(), span, K, b.recordLength_s() >= K * span ? "disjoint segments" : "offsets spread over twice its length"));
  if (rep->shared_sample_fraction > 0.0) {
    rep->notes.push_back(fmt::format("{:.0f} % of realization pairs take the same lab sample at the same field time "
                                     "(a fixed grafting.start_offset_s): their lab noise is shared",
                                     100.0 * rep->shared_sample_fraction));
  }
  const auto& cfg = st.c.config;
  if (cfg.reference_imu && cfg.reference_imu_noise_given) {
    const Eigen::Vector2d f = referenceResidualFraction(*cfg.reference_imu, *cfg.tested_imu);
    rep->notes.push_back(fmt::format(
        "the reference IMU's own white noise, grafted along, is {:.2f} % (gyro) and {:.2f} % (accel) "
        "of the tested IMU's",
        100.0 * f[0], 100.0 * f[1]));
  }
  if (K < 19) {
    rep->notes.push_back(fmt::format("{} realizations: the [p05, p95] interval covers about {:.0f} % of "
                                     "realizations, not 90 % (use 19 or more)",
                                     K, 100.0 * (K - 1) / (K + 1)));
  }
}

void writeSgOutputs(const SgEvaluateOptions& o, const SgEvaluationReport& rep, const LogFn& log) {
  const fs::path out(o.out_dir);
  for (const auto& s : rep.solutions) {
    writeErrorsCsv((out / ("errors_" + s.label + ".csv")).string(), s.evaluation, 1.0 / rep.csv_rate_hz);
  }
  writeEvaluationJson((out / "evaluation.json").string(), rep);
  writeTablesMarkdown((out / "tables.md").string(), rep);
  writeEvaluationCsv((out / "evaluation.csv").string(), rep);
  writePredictiveCsv((out / "predictive.csv").string(), rep);
  writePerOutageCsv((out / "outage_drift.csv").string(), rep);
  if (o.plots) {
    const std::string w = runPythonScript("plot_sg.py", {o.out_dir});
    if (!w.empty()) log("warning: " + w);
  }
}

}  // namespace

SgEvaluationReport runSgEvaluation(const SgEvaluateOptions& o, const LogFn& log_in) {
  const LogFn log = log_in ? log_in : [](const std::string&) {};
  for (const auto& w : checkEvaluationInputs(o)) log("warning: " + w);  // before any output
  const std::string tag = fs::path(o.case_dir).filename().string();
  Setup st;
  st.c = loadCaseInputs(o.case_dir);
  for (const auto& w : st.c.warnings) log("warning: " + w);
  const CaseConfig& cfg = st.c.config;
  if (!cfg.tested_imu || !cfg.tested_imu_noise_given) {
    throw std::runtime_error(st.c.paths().caseYaml() +
                             ": tested_imu needs its noise parameters (arw_deg_rt_h, vrw_m_s_rt_h, "
                             "gyro_bias_instability_deg_h, accel_bias_instability_mg) to be navigated");
  }
  std::vector<std::string> cw;
  if (!o.config_path.empty()) st.rc = loadRunConfig(o.config_path, &cw);
  for (const auto& w : cw) log("warning: " + w);
  validateOptions(o, st.rc);
  OutageScheduleConfig oc = st.rc.outages;
  if (o.outage_length_s) oc.length_s = *o.outage_length_s;
  if (o.outage_period_s) oc.period_s = *o.outage_period_s;
  if (o.outage_start_s) oc.start_s = *o.outage_start_s;
  const int K = o.realizations.value_or(st.rc.grafting.realizations);
  const int N = o.outage_shifts.value_or(st.rc.grafting.outage_shifts);
  st.schedules = shiftedSchedules(oc, N);

  SgEvaluationReport rep;
  rep.case_name = cfg.name;
  rep.estimator = o.estimator;
  rep.tested_grade = cfg.tested_imu->grade;
  rep.realizations = K;
  rep.csv_rate_hz = st.rc.evaluation.csv_rate_hz;
  rep.outage_shifts = N;
  for (const auto& s : st.schedules) rep.shift_starts_s.push_back(s.start_s);

  st.ref = selectImu(st.c, "ref");
  const double t_first = st.ref.imu.front().t_s - st.ref.imu.front().dt_s;
  const double t_last = st.ref.imu.back().t_s;
  for (const auto& s : st.schedules) {
    if (buildOutageWindows(s, t_first, t_last).empty()) {
      throw std::runtime_error(fmt::format(
          "no GNSS outage fits in the data of '{}' ({:.1f} s of IMU data) with outages of {:g} s every "
          "{:g} s starting {:g} s after the first epoch and ending {:g} s before the last: nothing to "
          "evaluate (set --outage-start / --outage-period / --outage-length)",
          o.case_dir, t_last - t_first, s.length_s, s.period_s, s.start_s, s.end_margin_s));
    }
  }

  // 1. Lab calibration and the basic error signal.
  log(fmt::format("[{}] calibrating the tested IMU from lab/", tag));
  const LabCalibrationReport labrep = calibrateLab(loadLabData(o.case_dir));
  for (const auto& n : labrep.notes) rep.notes.push_back("calibration: " + n);
  st.plan = makeGraftPlan(labrep, o.use_cross_axis);

  // 2. The realizations.
  RealizationOptions ro;
  ro.count = K;
  ro.seed = o.seed;
  ro.vary_segment = st.rc.grafting.start_offset_s < 0.0;
  st.draws = drawRealizations(ro, st.plan->basic, *cfg.tested_imu, t_last - t_first);
  if (!ro.vary_segment)
    for (auto& d : st.draws) d.start_offset_s = st.rc.grafting.start_offset_s;
  describeRealizations(st, K, &rep);
  if (CasePaths::exists(st.c.paths().testedImu())) {
    st.real = selectImu(st.c, "tested");
  } else {
    rep.notes.push_back("no field/tested_imu.txt: ERR_REAL, DIFF and the verdicts are not available");
  }
  st.sol_ref = solutionReference(o, st, &rep, log, tag);

  // 3. Navigate every unit; only now are files written.
  fs::create_directories(o.out_dir);
  writeCalibrationYaml((fs::path(o.out_dir) / "calibration.yaml").string(), labrep.result);
  if (o.write_grafted_imu) {
    for (SgStrategy g : {SgStrategy::kBasic, SgStrategy::kFull}) {
      writeImu((fs::path(o.out_dir) / (std::string("IMU_") + sgLabel(g) + ".txt")).string(),
               graftSeries(st.ref.imu, *st.plan, g, graftOptionsFor(st.draws.front())));
    }
  }
  const std::vector<Unit> units = makeUnits(st.real.has_value(), K, N);
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int jobs = std::max(1, std::min<int>(units.size(), o.jobs > 0 ? o.jobs : hw));
  log(fmt::format("[{}] navigating {} realizations of SG1 and SG2{} with {} at {} outage schedule(s) "
                  "({} navigations, {} in parallel)",
                  tag, K, st.real ? " and REAL" : "", o.estimator, N, units.size(), jobs));
  std::vector<UnitResult> results = navigateAll(units, st, o.estimator, jobs, log, tag);
  // The first unit (REAL, else SG1 realization 0, at the first schedule) says what was assumed.
  for (const auto& s : results.front().notes) rep.notes.push_back(s);
  rep.outages = buildOutageWindows(st.schedules.front(), t_first, t_last);
  rep.outage_length_s = rep.outages.front().length_s();
  summarize(units, results, st, K, o, &rep);
  writeSgOutputs(o, rep, log);
  return rep;
}

}  // namespace graftnav::app
