#include "graftnav/navigate/navigate_run.h"

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>

#include "graftnav/case/file_streams.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/solution_files.h"
#include "graftnav/eval/errors_csv.h"
#include "graftnav/eval/evaluation_files.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/io/nav_io.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

// Called on the finished run before its files are committed (a failing check leaves none).
using BeforeCommitFn = std::function<void(const NavSolution&)>;
// Writes errors.csv (from the evaluation held in memory, or the streamed evaluation's file).
using ErrorsCsvFn = std::function<void(const std::string& path)>;

// Streamed run: the IMU read in blocks, the files written as it goes, each epoch evaluated against
// the reference as it comes when `evaluation` is given; the returned solution holds the counts
// only. Byte-identical files to inMemoryRun's.
NavSolution streamedRun(const NavigateSetup& s, const fs::path& out,
                        const EstimatorRegistry& registry, StreamedEvaluation* evaluation,
                        const BeforeCommitFn& before_commit, RunFiles* files) {
  NavSolution sol;
  // An estimator without scale-factor series (the factor graphs unless their options add them)
  // writes no imu_errors.txt, as in memory.
  const bool with_imu_errors = registry.find(s.estimator).estimatesScaleFactors(s.pr, s.rc);
  SolutionFileSink sink(out.string(), with_imu_errors, evaluation);
  const NavSolution book =
      registry.runStreaming(s.estimator, s.pr, imuRangeStream(s.imu, s.time_range), s.rc, sink);
  sol.copyBookkeeping(book);
  if (const auto& scale = sink.lastOdometerScale()) {
    sol.odometer_scale = {scale->scale};
    sol.odometer_scale_std = {scale->std};
  }
  before_commit(sol);
  *files = sink.commit();
  return sol;
}

NavSolution inMemoryRun(const NavigateSetup& s, const fs::path& out,
                        const EstimatorRegistry& registry, const ProgressFn& progress,
                        const BeforeCommitFn& before_commit, RunFiles* files) {
  NavSolution sol = registry.run(s.estimator, s.pr, s.rc, progress);
  before_commit(sol);
  writeNav((out / "solution.nav").string(), sol.states);
  files->epochs = sol.states.size();
  files->imu_errors = writeImuErrors((out / "imu_errors.txt").string(), sol);
  files->state_std = writeStateStd((out / "state_std.txt").string(), sol);
  writeOdometerScale((out / "odometer_scale.txt").string(), sol);
  return sol;
}

// The evaluation of a streamed run against its streamed reference (null otherwise): errors.csv
// is written as the epochs come and committed with the other evaluation files.
std::unique_ptr<StreamedEvaluation> streamedEvaluation(const NavigateSetup& s,
                                                       const fs::path& out) {
  if (!s.stream || s.streamed_reference.path.empty()) return nullptr;
  const CaseReferenceFile& f = s.streamed_reference;
  const std::string csv = (out / "errors.csv").string();
  const double csv_interval_s = 1.0 / s.rc.evaluation.csv_rate_hz;
  return std::make_unique<StreamedEvaluation>(
      std::make_unique<NavStreamReader>(f.path, f.policy), s.pr.outages, s.rc.evaluation.options,
      s.estimator, s.expected_rates,
      [csv, csv_interval_s]() { return std::make_unique<ErrorsCsvWriter>(csv, csv_interval_s); });
}

ReportMeta reportMeta(const NavigateSetup& s) {
  ReportMeta meta;
  meta.estimator = s.estimator;
  meta.imu = s.imu.label;
  meta.outage_count = static_cast<int>(s.pr.outages.size());
  meta.outage_length_s = s.pr.outages.empty()            ? 0.0
                         : s.oc.explicit_windows.empty() ? s.oc.length_s
                                                         : s.pr.outages.front().length_s();
  return meta;
}

// errors.json, run_info.json, errors.csv and outage_drift.csv.
void writeEvaluation(const NavigateSetup& s, const fs::path& out, const Evaluation& ev,
                     const ErrorsCsvFn& write_errors_csv, const NavSolution& sol, double run_time,
                     std::vector<std::string> notes, const RunMessages& messages) {
  const ReportMeta meta = reportMeta(s);
  notes.push_back("reference: " + s.c.reference_name);
  std::vector<std::string> warnings = writeErrorsJson((out / "errors.json").string(), meta, ev);
  const auto run_info_warnings = writeRunInfoJson((out / "run_info.json").string(), meta, ev, sol,
                                                  s.pr.outages, notes, run_time);
  warnings.insert(warnings.end(), run_info_warnings.begin(), run_info_warnings.end());
  write_errors_csv((out / "errors.csv").string());
  writeOutageCsv((out / "outage_drift.csv").string(), ev);
  for (const auto& w : warnings) messages.warning(w);
}

}  // namespace

NavigateOutcome runNavigate(const NavigateSetup& s, const std::string& out_dir,
                            const EstimatorRegistry& registry, const RunMessages& messages,
                            const ProgressFn& progress) {
  std::vector<std::string> notes = s.notes;
  const BeforeCommitFn check = [&](const NavSolution& sol) {
    for (const auto& w : checkGnssUsed(sol.gnss_used, !s.uses_gnss)) {
      messages.warning(w);
      notes.push_back(w);
    }
  };
  const fs::path out(out_dir);
  NavigateOutcome o;
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<StreamedEvaluation> evaluation = streamedEvaluation(s, out);
  o.solution = s.stream ? streamedRun(s, out, registry, evaluation.get(), check, &o.files)
                        : inMemoryRun(s, out, registry, progress, check, &o.files);
  o.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (!s.hasReference()) {
    for (const auto& w : writeRunInfoJson(
             (out / "run_info.json").string(), ReportMeta{s.estimator, s.imu.label, 0, 0.0},
             Evaluation{}, o.solution, s.pr.outages, notes, o.run_time_s))
      messages.warning(w);
    return o;
  }
  if (evaluation) {
    o.evaluation = evaluation->finish();
    writeEvaluation(
        s, out, *o.evaluation, [&](const std::string&) { evaluation->commitEpochs(); }, o.solution,
        o.run_time_s, notes, messages);
  } else {
    o.evaluation =
        evaluateSolution(o.solution, s.c.reference, s.pr.outages, s.rc.evaluation.options);
    const double csv_interval_s = 1.0 / s.rc.evaluation.csv_rate_hz;
    writeEvaluation(
        s, out, *o.evaluation,
        [&](const std::string& path) { writeErrorsCsv(path, *o.evaluation, csv_interval_s); },
        o.solution, o.run_time_s, notes, messages);
  }
  return o;
}

}  // namespace graftnav
