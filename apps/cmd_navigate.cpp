// graftnav navigate CASE_DIR --out OUT_DIR [--imu ref|tested|FILE] [--profile FILE]
//   [--estimator ekf,rts,...] [--outage-length S --outage-period S --outage-start S]
//   [--run-config FILE] [--start T --end T] [--decimate N] [--lenient] [--no-plots]
// Several estimators write OUT_DIR/<estimator>/. Without --run-config, CASE_DIR/run.yaml is used
// when present (written by `graftnav import`). Estimators with a streamed form (ekf, rts, fgo,
// fgo-window) read the IMU in blocks and the GNSS epoch by epoch (unless the run config selects
// GNSS epochs) and write their per-epoch files as they go (streamedRun).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "graftnav/case/case_inputs.h"
#include "graftnav/case/problem.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/io/case_config.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/estimation/alignment.h"
#include "cli_vocabulary.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/io/provenance.h"
#include "graftnav/case/file_streams.h"
#include "graftnav/case/solution_files.h"
#include "graftnav/eval/evaluation_files.h"
#include "graftnav/case/run_config.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

struct NavigateArgs {
  std::string case_dir, out, imu, profile, estimator = "ekf", config;
  OutageOverrides outage;
  bool free_inertial = false, lenient = false, no_plots = false;
  int decimate = 1;
  TimeRangeConfig time_range;
};

// The error summary of a run against its truth or reference, on stdout.
void printEvaluation(const Evaluation& ev) {
  const double r2d = kRadToDeg;
  fmt::print(
      "  overall RMS: horizontal {:.3f} m, vertical {:.3f} m, roll {:.4f}, pitch {:.4f}, "
      "heading {:.4f} deg\n",
      ev.overall_rms.horizontal_m, ev.overall_rms.vertical_m, ev.overall_rms.roll_rad * r2d,
      ev.overall_rms.pitch_rad * r2d, ev.overall_rms.heading_rad * r2d);
  if (!ev.outages.empty()) {
    fmt::print(
        "  outages ({}): RMS over outage epochs: horizontal {:.3f} m, vertical {:.3f} m, "
        "roll {:.4f}, pitch {:.4f}, heading {:.4f} deg\n",
        ev.outages.size(), ev.outage_rms.horizontal_m, ev.outage_rms.vertical_m,
        ev.outage_rms.roll_rad * r2d, ev.outage_rms.pitch_rad * r2d,
        ev.outage_rms.heading_rad * r2d);
    fmt::print(
        "  outages: RMS of per-outage maxima: horizontal {:.3f} m, vertical {:.3f} m, "
        "heading {:.4f} deg\n",
        ev.outage_max_rms.horizontal_m, ev.outage_max_rms.vertical_m,
        ev.outage_max_rms.heading_rad * r2d);
  }
  if (ev.nees_samples > 0) {
    fmt::print("  NEES {:.2f} (9 PVA states, {} samples; 95% band [{:.2f}, {:.2f}])\n",
               ev.nees_mean, ev.nees_samples, ev.nees_band_low, ev.nees_band_high);
  }
}

// Prints the warnings and keeps them in the run's notes (run_info.json).
void warnAll(const std::vector<std::string>& warnings, std::vector<std::string>* notes) {
  for (const auto& w : warnings) {
    fmt::print(stderr, "warning: {}\n", w);
    notes->push_back(w);
  }
}

// Everything the run needs, validated before any output is written.
struct NavigateSetup {
  CaseInputs c;
  RunConfig rc;
  ImuSelection imu;
  OutageScheduleConfig oc;
  EstimationProblem pr;
  std::vector<std::string> notes;
  bool stream = false;       // the IMU read in blocks during the run; imu.imu and pr.imu not held
  bool stream_gnss = false;  // the GNSS read epoch by epoch during the run (pr.gnss_stream)
  long gnss_count = 0;       // GNSS epochs in the case
};

// Whether the run streams the IMU (read in blocks, the per-epoch files written as they go).
// In memory instead when the estimator has no streamed form or something needs the samples: a
// data alignment (rc.alignment.mode other than "given"), or a --start/--end time range
// (restrictToTimeRange cuts the series in memory).
bool streamable(const std::string& estimator, const RunConfig& rc, const TimeRangeConfig& range) {
  return estimatorTable().canStream(estimator) && rc.alignment.mode == "given" && range.empty();
}

// Whether a streamed run also reads the GNSS epoch by epoch: unless the run config selects GNSS
// epochs (selectGnss re-sorts and spaces the whole series).
bool streamsGnss(const NavigateArgs& a, const RunConfig& rc) {
  return !a.free_inertial &&
         streamable(a.estimator, rc, mergeTimeRange(rc.time_range, a.time_range)) && !rc.gnss.given;
}

// The case's GNSS read once epoch by epoch before anything is written, as scanStreamedImu reads
// the IMU: its errors stop the run here, its warnings are printed, the coverage check gets the
// counts. Memory stays flat; the run reads the files again through *stream. Returns the first
// epoch, which stands in for the series in makeProblem (it asks only whether there is GNSS).
GnssFix scanStreamedGnss(const NavigateArgs& a, NavigateSetup* s, GnssOpenFn* stream) {
  const CasePaths paths = s->c.paths();
  if (!CasePaths::exists(paths.gnssPos()))
    throw std::runtime_error("GNSS file '" + paths.gnssPos() + "' not found");
  const std::string ft = CasePaths::exists(paths.gnssFixType()) ? paths.gnssFixType() : "";
  const GnssReadPolicy policy = a.lenient ? GnssReadPolicy::real() : GnssReadPolicy{};
  GnssStreamReader reader(paths.gnssPos(), ft, policy);
  GnssCoverage coverage;
  coverage.imu_t0_s = s->imu.imu.front().t_s - s->imu.imu.front().dt_s;
  coverage.imu_t1_s = s->imu.imu.back().t_s;
  GnssFix fix, first;
  while (reader.next(&fix)) {
    if (coverage.total == 0) first = fix;
    coverage.add(fix.t_s);
  }
  for (const auto& r : reader.reports())
    if (!r.summary().empty()) fmt::print(stderr, "warning: {}\n", r.summary());
  warnAll(checkGnssCoverage(coverage, paths.gnssPos(), false), &s->notes);
  s->gnss_count = coverage.total;
  *stream = gnssFileStream(paths.gnssPos(), ft, policy);
  return first;
}

// A streamed IMU file read once through the block reader before anything is written, so that its
// errors (physical range, time order, intervals) stop the run here as readImu's would, the
// --lenient repair report is known, and makeProblem and the input checks get the first and last
// samples (initial time, span). Memory stays flat; the run reads the file again.
ImuSeries scanStreamedImu(ImuSelection* sel) {
  ImuBlockReader reader(sel->path, sel->read_options);
  ImuSeries block, span;
  while (reader.next(&block)) {
    if (span.empty()) span = {block.front(), block.back()};
    span.back() = block.back();
  }
  sel->read_summary = reader.report().summary();
  return span;
}

// The IMU and its profile (paths relative to the case or the working directory), read in memory
// and cut to the time range, or scanned for a streamed run.
void selectNavigateImu(const NavigateArgs& a, NavigateSetup* s) {
  const std::string imu_which =
      a.imu == "ref" || a.imu == "tested" ? a.imu : resolveUserPath(a.imu, a.case_dir, "IMU file");
  const std::string profile =
      a.profile.empty() ? a.profile : resolveUserPath(a.profile, a.case_dir, "IMU profile");
  if (!profile.empty()) recordConfigFile(profile);
  const TimeRangeConfig range = mergeTimeRange(s->rc.time_range, a.time_range);
  s->stream = streamable(a.free_inertial ? "free-inertial" : a.estimator, s->rc, range);
  s->imu = selectImu(s->c, imu_which, profile, a.lenient, !s->stream);
  if (s->stream) {
    s->imu.imu = scanStreamedImu(&s->imu);
  } else {
    restrictToTimeRange(range, &s->c, &s->imu, &s->notes);
  }
  if (!s->imu.read_summary.empty()) warnAll({s->imu.read_summary}, &s->notes);
  if (!a.free_inertial && !s->imu.profile_given) {
    throw std::runtime_error("no noise parameters for IMU '" + a.imu +
                             "' in case.yaml: pass --profile FILE (configs/imu/*.yaml)");
  }
}

NavigateSetup prepareNavigate(const NavigateArgs& a) {
  a.outage.validate();
  if (!a.free_inertial && !estimatorTable().contains(a.estimator))
    throw std::runtime_error("--estimator '" + a.estimator + "': unknown estimator");
  NavigateSetup s;
  // The run config first: whether the GNSS is held depends on it.
  std::vector<std::string> config_warnings;
  const std::string run_config = runConfigPathFor(a.config, a.case_dir);
  if (!run_config.empty()) s.rc = loadRunConfig(run_config, &config_warnings);
  s.stream_gnss = streamsGnss(a, s.rc);
  CaseLoadOptions lo;
  lo.load_gnss = !a.free_inertial && !s.stream_gnss;
  lo.lenient = a.lenient;
  s.c = loadCaseInputs(a.case_dir, lo);
  recordConfigFile(s.c.paths().caseYaml());
  std::vector<std::string> warnings = s.c.warnings;
  warnings.insert(warnings.end(), config_warnings.begin(), config_warnings.end());
  if (!run_config.empty()) {
    recordConfigFile(run_config);
    s.notes.push_back("run config: " + run_config);
    if (a.config.empty()) fmt::print(stderr, "note: using the case's run config {}\n", run_config);
  }
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  s.rc.ekf.output_decimation = a.decimate;
  if (a.free_inertial) s.rc.alignment.mode = "given";

  selectNavigateImu(a, &s);
  GnssOpenFn gnss_stream;
  if (s.stream_gnss) {
    s.c.gnss = {scanStreamedGnss(a, &s, &gnss_stream)};
  } else if (!a.free_inertial) {
    warnAll(checkGnssCoverage(s.c.gnss, s.c.paths().gnssPos(), s.imu.imu, false), &s.notes);
  }

  // Outages: config section, overridden by the command line; none for a free-inertial run.
  s.oc = a.outage.appliedTo(s.rc.outages);
  std::optional<OutageScheduleConfig> outages;
  if ((s.rc.outages_given || a.outage.any()) && !a.free_inertial) outages = s.oc;
  s.pr = makeProblem(s.c, s.imu, s.rc, outages, &s.notes);
  if (s.stream_gnss) {  // makeProblem saw the first epoch only; the run reads the files
    s.pr.gnss = {};
    s.c.gnss = {};
    s.pr.gnss_stream = gnss_stream;
  } else {
    s.gnss_count = static_cast<long>(s.pr.gnss.size());
  }
  for (const auto& n : s.notes)
    if (n.find("alignment") != std::string::npos || n.find("lever") != std::string::npos ||
        n.find("GNSS selection") != std::string::npos ||
        n.find("time range") != std::string::npos || n.find("odometer") != std::string::npos)
      fmt::print(stderr, "note: {}\n", n);
  if (outages) {
    const double t0 = s.pr.imu.front().t_s - s.pr.imu.front().dt_s;
    requireOutagesInsideData(*outages, s.pr.outages, t0, s.pr.imu.back().t_s);
  }
  warnAll(checkReferenceCoverage(s.c.reference, s.c.reference_name, s.pr.imu, s.pr.outages),
          &s.notes);
  if (s.stream) {  // the checks above needed only the span; the run reads the file in blocks
    s.pr.imu = {};
    s.imu.imu = {};
  }
  return s;
}

// errors.json, run_info.json, errors.csv, outage_drift.csv and the console summary.
void writeEvaluation(const NavigateArgs& a, const NavigateSetup& s, const std::string& estimator,
                     const NavSolution& sol, double run_time, std::vector<std::string> notes) {
  const Evaluation ev = evaluateSolution(sol, s.c.reference, s.pr.outages, s.rc.evaluation.options);
  ReportMeta meta;
  meta.estimator = estimator;
  meta.imu = s.imu.label;
  meta.outage_count = static_cast<int>(s.pr.outages.size());
  meta.outage_length_s = s.pr.outages.empty()            ? 0.0
                         : s.oc.explicit_windows.empty() ? s.oc.length_s
                                                         : s.pr.outages.front().length_s();
  notes.push_back("reference: " + s.c.reference_name);
  const fs::path out(a.out);
  std::vector<std::string> warnings = writeErrorsJson((out / "errors.json").string(), meta, ev);
  const auto run_info_warnings = writeRunInfoJson((out / "run_info.json").string(), meta, ev, sol,
                                                  s.pr.outages, notes, run_time);
  warnings.insert(warnings.end(), run_info_warnings.begin(), run_info_warnings.end());
  writeErrorsCsv((out / "errors.csv").string(), ev, 1.0 / s.rc.evaluation.csv_rate_hz);
  writeOutageCsv((out / "outage_drift.csv").string(), ev);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  printEvaluation(ev);
  fmt::print("  wrote errors.json, run_info.json, errors.csv, outage_drift.csv in {}\n", a.out);
}

// The per-epoch files of a run (solution.nav, imu_errors.txt, state_std.txt): what was written.
struct RunFiles {
  std::size_t epochs = 0;
  bool imu_errors = false, state_std = false;
};
// Called on the finished run before its files are committed (a failing check leaves none).
using BeforeCommitFn = std::function<void(const NavSolution&)>;

// Writes the per-epoch files as the epochs come; also appends them to a NavSolution when given
// (the evaluation against a reference needs them).
class NavFileSink : public SolutionSink {
 public:
  NavFileSink(const fs::path& out, bool with_imu_errors, NavSolution* keep)
      : nav_((out / "solution.nav").string()),
        outputs_((out / "imu_errors.txt").string(), (out / "state_std.txt").string(),
                 with_imu_errors, (out / "odometer_scale.txt").string()) {
    if (keep) keep_.emplace(keep);
  }
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& sensors) override {
    nav_.add(state);
    outputs_.add(state, sigma, sensors);
    if (keep_) keep_->add(state, sigma, sensors);
  }
  void addOdometerScale(const OdometerScaleEstimate& estimate) override {
    outputs_.addOdometerScale(estimate);
    if (keep_) keep_->addOdometerScale(estimate);
  }
  RunFiles commit() {
    RunFiles f;
    nav_.commit();
    f.epochs = nav_.count();
    outputs_.commit(&f.imu_errors, &f.state_std);
    return f;
  }

 private:
  NavWriter nav_;
  SolutionOutputsSink outputs_;
  std::optional<NavSolutionSink> keep_;
};

// Streamed run: the IMU read in blocks, the files written as it goes; the epochs are kept in the
// returned solution only when `keep`. Byte-identical files to inMemoryRun's.
NavSolution streamedRun(const std::string& estimator, const NavigateSetup& s, const fs::path& out,
                        bool keep, const BeforeCommitFn& before_commit, RunFiles* files) {
  NavSolution sol;
  // An estimator without scale-factor series (the factor graphs) writes no imu_errors.txt, as in
  // memory.
  const bool with_imu_errors = estimatorTable().find(estimator).estimates_scale_factors;
  NavFileSink sink(out, with_imu_errors, keep ? &sol : nullptr);
  const NavSolution book = estimatorTable().runStreaming(
      estimator, s.pr, imuFileStream(s.imu.path, s.imu.read_options), s.rc, sink);
  sol.estimator = book.estimator;
  sol.gnss_used = book.gnss_used;
  sol.gnss_rejected = book.gnss_rejected;
  sol.gnss_withheld = book.gnss_withheld;
  sol.vehicle_used = book.vehicle_used;
  sol.vehicle_rejected = book.vehicle_rejected;
  before_commit(sol);
  *files = sink.commit();
  return sol;
}

NavSolution inMemoryRun(const std::string& estimator, const NavigateSetup& s, const fs::path& out,
                        const ProgressFn& progress, const BeforeCommitFn& before_commit,
                        RunFiles* files) {
  NavSolution sol = estimatorTable().run(estimator, s.pr, s.rc, progress);
  before_commit(sol);
  writeNav((out / "solution.nav").string(), sol.states);
  files->epochs = sol.states.size();
  files->imu_errors = writeImuErrors((out / "imu_errors.txt").string(), sol);
  files->state_std = writeStateStd((out / "state_std.txt").string(), sol);
  writeOdometerScale((out / "odometer_scale.txt").string(), sol);
  return sol;
}

void runNavigateOne(const NavigateArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  fmt::print(stderr, "[{:6.1f} s] reading the case and the {} IMU\n", elapsed(), a.imu);
  const NavigateSetup s = prepareNavigate(a);
  // Created before the run so that an unusable --out fails now, not after the filter.
  fs::create_directories(a.out);

  const std::string estimator = a.free_inertial ? "free-inertial" : a.estimator;
  if (s.stream) {
    fmt::print(stderr,
               "[{:6.1f} s] streaming the {} IMU: {} on {} in blocks, {} GNSS fixes, {} outages\n",
               elapsed(), a.imu, estimator, s.imu.path, s.gnss_count, s.pr.outages.size());
  } else {
    fmt::print(stderr, "[{:6.1f} s] {} on {} IMU samples, {} GNSS fixes, {} outages\n", elapsed(),
               estimator, s.pr.imu.size(), s.gnss_count, s.pr.outages.size());
  }
  int last_decile = -1;
  const ProgressFn progress = [&](double f) {
    const int d = static_cast<int>(f * 10.0);
    if (d != last_decile) {
      last_decile = d;
      fmt::print(stderr, "[{:6.1f} s] {} {:3d} %\n", elapsed(), estimator, d * 10);
    }
  };
  std::vector<std::string> notes = s.notes;
  const BeforeCommitFn check = [&](const NavSolution& sol) {
    warnAll(checkGnssUsed(sol.gnss_used, a.free_inertial), &notes);
  };
  const fs::path out_dir(a.out);
  const double t_run0 = elapsed();
  RunFiles files;
  const NavSolution sol =
      s.stream ? streamedRun(estimator, s, out_dir, !s.c.reference.empty(), check, &files)
               : inMemoryRun(estimator, s, out_dir, progress, check, &files);
  const double run_time = elapsed() - t_run0;

  fmt::print("{}: {} epochs -> {} ({:.2f} s)\n", estimator, files.epochs,
             (out_dir / "solution.nav").string(), run_time);
  if (files.imu_errors) fmt::print("  wrote imu_errors.txt\n");
  if (files.state_std) fmt::print("  wrote state_std.txt\n");
  if (!a.free_inertial) {
    fmt::print("  GNSS used {}, rejected by the gate {}, withheld in outages {}\n", sol.gnss_used,
               sol.gnss_rejected, sol.gnss_withheld);
  }
  if (s.c.reference.empty()) {
    for (const auto& w : writeRunInfoJson((out_dir / "run_info.json").string(),
                                          ReportMeta{estimator, s.imu.label, 0, 0.0}, Evaluation{},
                                          sol, s.pr.outages, notes, run_time))
      fmt::print(stderr, "warning: {}\n", w);
    fmt::print(
        "  no field/truth.nav or reference solution: no errors written (run_info.json only)\n");
    return;
  }
  writeEvaluation(a, s, estimator, sol, run_time, notes);
  if (!a.no_plots) {
    const std::string w = runPythonScript("plot_errors.py", {a.out});
    if (!w.empty()) {
      fmt::print(stderr, "warning: {}\n", w);
    } else {
      fmt::print("  wrote error plots (errors_*.png) in {}\n", a.out);
    }
  }
}

// Several estimators run one after the other into OUT/<estimator>/; every name is checked first.
void runNavigate(const NavigateArgs& a) {
  const std::vector<std::string> estimators =
      a.free_inertial ? std::vector<std::string>{"free-inertial"} : splitEstimatorList(a.estimator);
  for (const auto& e : estimators)
    if (!estimatorTable().contains(e))
      throw std::runtime_error("--estimator '" + e + "': unknown estimator");
  for (const auto& e : estimators) {
    NavigateArgs one = a;
    one.estimator = e;
    one.free_inertial = e == "free-inertial";
    if (estimators.size() > 1) one.out = (fs::path(a.out) / e).string();
    runNavigateOne(one);
  }
}

}  // namespace

void registerNavigate(CLI::App& app) {
  auto a = std::make_shared<NavigateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "navigate", "GNSS/INS navigation of a case (EKF, RTS, ... or free inertial) and its errors");
  cmd->add_option("case_dir", a->case_dir, "case directory (case.yaml, field/...)")->required();
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--imu", a->imu,
                  "ref | tested | path of an IMU file (default: ref, else the case's only IMU)");
  cmd->add_option("--profile", a->profile, "IMU profile YAML (default: from case.yaml)");
  cmd->add_option("--estimator", a->estimator,
                  "comma list of " + estimatorTable().namesText() + " (default ekf)");
  cmd->add_option("--outage-length", a->outage.length_s, "GNSS outage length (s)");
  cmd->add_option("--outage-period", a->outage.period_s, "outage start-to-start period (s)");
  cmd->add_option("--outage-start", a->outage.start_s,
                  "first outage start after the data start (s)");
  cmd->add_option("--run-config", a->config,
                  "run config YAML (configs/navigate.yaml; default CASE/run.yaml)");
  addDeprecatedOption(cmd, "--config", "--run-config", &a->config);
  addDeprecatedFlag(cmd, "--free-inertial", "--estimator free-inertial", &a->free_inertial);
  addTimeRangeOptions(cmd, &a->time_range);
  cmd->add_option("--decimate", a->decimate, "write every N-th IMU epoch (default 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--lenient", a->lenient, "real-data read policies (repair/warn instead of error)");
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/runtime/plot_errors.py");
  cmd->callback([a]() {
    a->imu = imuChoice(a->imu, a->case_dir);
    runNavigate(*a);
  });
}

}  // namespace graftnav::app
