// graftnav navigate CASE_DIR --out OUT_DIR [--imu ref|tested|FILE] [--profile FILE]
//   [--estimator ekf|rts|...] [--outage-length S --outage-period S --outage-start S]
//   [--config FILE] [--free-inertial] [--decimate N] [--lenient] [--no-plots]
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "case_loader.h"
#include "estimators.h"
#include "graftnav/io/case_config.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/filters/alignment.h"
#include "report_io.h"
#include "run_config.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

// Writes solution.nav as the epochs come; also appends them to a NavSolution when given.
class NavFileSink : public SolutionSink {
 public:
  NavFileSink(const std::string& path, NavSolution* keep) : writer_(path) {
    if (keep) keep_.emplace(keep);
  }
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& sensors) override {
    writer_.add(state);
    if (keep_) keep_->add(state, sigma, sensors);
  }
  std::size_t commit() {
    writer_.commit();
    return writer_.count();
  }

 private:
  NavWriter writer_;
  std::optional<NavSolutionSink> keep_;
};

// The first and last sample of a file that is to be streamed, for makeProblem (the initial
// time, the outage schedule's span) without reading the rest.
ImuSeries imuSpan(const ImuSelection& sel) {
  ImuBlockReader head(sel.path, sel.read_options, 1);
  ImuSeries first;
  head.next(&first);
  ImuSample last = first.front();
  last.t_s = std::max(first.front().t_s, readLastImuTime(sel.path));
  return {first.front(), last};
}

// Streamed run: the IMU read in blocks, solution.nav written as it goes; the epochs are kept in
// the returned solution only when `keep` (the errors against a reference need them).
NavSolution streamSolution(const std::string& estimator, const EstimationProblem& pr, const ImuSelection& imu,
                           const RunConfig& rc, const std::string& nav_out, bool keep, std::size_t* epochs) {
  NavSolution sol;
  NavFileSink sink(nav_out, keep ? &sol : nullptr);
  const NavSolution book = runEstimatorStreaming(estimator, pr, imuFileStream(imu.path, imu.read_options), rc, sink);
  sol.estimator = book.estimator;
  sol.gnss_used = book.gnss_used;
  sol.gnss_rejected = book.gnss_rejected;
  sol.gnss_withheld = book.gnss_withheld;
  *epochs = sink.commit();
  return sol;
}

NavSolution writeSolution(NavSolution sol, const std::string& nav_out, std::size_t* epochs) {
  writeNav(nav_out, sol.states);
  *epochs = sol.states.size();
  return sol;
}

struct NavigateArgs {
  std::string case_dir, out, imu = "ref", profile, estimator = "ekf", config;
  double outage_length = -1, outage_period = -1, outage_start = -1;
  bool free_inertial = false, lenient = false, no_plots = false;
  int decimate = 1;
};

void runNavigate(const NavigateArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  CaseLoadOptions lo;
  lo.load_gnss = !a.free_inertial;
  lo.lenient = a.lenient;
  const CaseInputs c = loadCaseInputs(a.case_dir, lo);
  std::vector<std::string> warnings = c.warnings, notes;
  RunConfig rc;
  if (!a.config.empty()) rc = loadRunConfig(a.config, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  rc.ekf.output_decimation = a.decimate;
  if (a.free_inertial) rc.alignment.mode = "given";

  // Estimators with a streamed form read the IMU in blocks and write the solution as they go,
  // when nothing else needs the samples in memory (a data alignment does).
  const std::string estimator = a.free_inertial ? "free-inertial" : a.estimator;
  const bool stream = canStream(estimator) && rc.alignment.mode == "given";
  fmt::print(stderr, "[{:6.1f} s] {} the {} IMU\n", elapsed(), stream ? "streaming" : "reading", a.imu);
  ImuSelection imu = selectImu(c, a.imu, a.profile, a.lenient, !stream);
  if (stream) imu.imu = imuSpan(imu);
  if (!a.free_inertial && !imu.profile_given) {
    throw std::runtime_error("no noise parameters for IMU '" + a.imu +
                             "' in case.yaml: pass --profile FILE (configs/imu/*.yaml)");
  }
  const std::string imu_label = imu.label;
  const NavSeries& reference = c.reference;
  const std::string& reference_name = c.reference_name;

  // Outages: config section, overridden by the command line; none for a free-inertial run.
  const bool cli_outage = a.outage_length >= 0 || a.outage_period >= 0 || a.outage_start >= 0;
  OutageScheduleConfig oc = rc.outages;
  if (a.outage_length >= 0) oc.length_s = a.outage_length;
  if (a.outage_period >= 0) oc.period_s = a.outage_period;
  if (a.outage_start >= 0) oc.start_s = a.outage_start;
  std::optional<OutageScheduleConfig> outages;
  if ((rc.outages_given || cli_outage) && !a.free_inertial) outages = oc;
  EstimationProblem pr = makeProblem(c, imu, rc, outages, &notes);
  if (stream) pr.imu = {};  // read again in blocks
  for (const auto& n : notes)
    if (n.find("alignment") != std::string::npos || n.find("lever") != std::string::npos ||
        n.find("GNSS selection") != std::string::npos)
      fmt::print(stderr, "note: {}\n", n);

  if (stream) {
    fmt::print(stderr, "[{:6.1f} s] {} on {} in blocks, {} GNSS fixes, {} outages\n", elapsed(), estimator,
               imu.path, pr.gnss.size(), pr.outages.size());
  } else {
    fmt::print(stderr, "[{:6.1f} s] {} on {} IMU samples, {} GNSS fixes, {} outages\n", elapsed(), estimator,
               pr.imu.size(), pr.gnss.size(), pr.outages.size());
  }
  int last_decile = -1;
  const ProgressFn progress = [&](double f) {
    const int d = static_cast<int>(f * 10.0);
    if (d != last_decile) {
      last_decile = d;
      fmt::print(stderr, "[{:6.1f} s] {} {:3d} %\n", elapsed(), estimator, d * 10);
    }
  };
  fs::create_directories(a.out);
  const std::string nav_out = (fs::path(a.out) / "solution.nav").string();
  const double t_run0 = elapsed();
  std::size_t epochs = 0;
  const NavSolution sol = stream ? streamSolution(estimator, pr, imu, rc, nav_out, !reference.empty(), &epochs)
                                 : writeSolution(runEstimator(estimator, pr, rc, progress), nav_out, &epochs);
  const double run_time = elapsed() - t_run0;
  fmt::print("{}: {} epochs -> {} ({:.2f} s)\n", estimator, epochs, nav_out, run_time);
  if (!a.free_inertial) {
    fmt::print("  GNSS used {}, rejected by the gate {}, withheld in outages {}\n", sol.gnss_used,
               sol.gnss_rejected, sol.gnss_withheld);
  }
  if (reference.empty()) {
    fmt::print("  no field/truth.nav or reference solution: no errors written\n");
    return;
  }
  const Evaluation ev = evaluateSolution(sol, reference, pr.outages, rc.evaluation.options);
  ReportMeta meta;
  meta.estimator = estimator;
  meta.imu = imu_label;
  meta.outage_count = static_cast<int>(pr.outages.size());
  meta.outage_length_s = pr.outages.empty() ? 0.0 : oc.explicit_windows.empty() ? oc.length_s
                                                                                 : pr.outages.front().length_s();
  notes.push_back("reference: " + reference_name);
  const fs::path out(a.out);
  writeErrorsJson((out / "errors.json").string(), meta, ev);
  writeRunInfoJson((out / "run_info.json").string(), meta, ev, sol, pr.outages, notes, run_time);
  writeErrorsCsv((out / "errors.csv").string(), ev, 1.0 / rc.evaluation.csv_rate_hz);
  writeOutageCsv((out / "outage_drift.csv").string(), ev);
  const double r2d = kRadToDeg;
  fmt::print("  overall RMS: horizontal {:.3f} m, vertical {:.3f} m, roll {:.4f}, pitch {:.4f}, "
             "heading {:.4f} deg\n",
             ev.overall_rms.horizontal_m, ev.overall_rms.vertical_m, ev.overall_rms.roll_rad * r2d,
             ev.overall_rms.pitch_rad * r2d, ev.overall_rms.heading_rad * r2d);
  if (!ev.outages.empty()) {
    fmt::print("  outages ({}): RMS over outage epochs: horizontal {:.3f} m, vertical {:.3f} m, "
               "roll {:.4f}, pitch {:.4f}, heading {:.4f} deg\n",
               ev.outages.size(), ev.outage_rms.horizontal_m, ev.outage_rms.vertical_m,
               ev.outage_rms.roll_rad * r2d, ev.outage_rms.pitch_rad * r2d,
               ev.outage_rms.heading_rad * r2d);
    fmt::print("  outages: RMS of per-outage maxima: horizontal {:.3f} m, vertical {:.3f} m, "
               "heading {:.4f} deg\n",
               ev.outage_max_rms.horizontal_m, ev.outage_max_rms.vertical_m,
               ev.outage_max_rms.heading_rad * r2d);
  }
  if (ev.nees_samples > 0) {
    fmt::print("  NEES {:.2f} (9 PVA states, {} samples; 95% band [{:.2f}, {:.2f}])\n", ev.nees_mean,
               ev.nees_samples, ev.nees_band_low, ev.nees_band_high);
  }
  fmt::print("  wrote errors.json, run_info.json, errors.csv, outage_drift.csv in {}\n", a.out);
  if (!a.no_plots) {
    const std::string w = runPythonScript("plot_errors.py", {a.out});
    if (!w.empty()) {
      fmt::print(stderr, "warning: {}\n", w);
    } else {
      fmt::print("  wrote error plots (errors_*.png) in {}\n", a.out);
    }
  }
}

}  // namespace

void registerNavigate(CLI::App& app) {
  auto a = std::make_shared<NavigateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "navigate", "GNSS/INS navigation of a case (EKF, RTS, ... or free inertial) and its errors");
  cmd->add_option("case_dir", a->case_dir, "case directory (case.yaml, field/...)")->required();
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--imu", a->imu, "ref | tested | path of an IMU file (default ref)");
  cmd->add_option("--profile", a->profile, "IMU profile YAML (default: from case.yaml)")
      ->check(CLI::ExistingFile);
  std::string names;
  for (const auto& n : estimatorNames()) names += (names.empty() ? "" : " | ") + n;
  cmd->add_option("--estimator", a->estimator, "estimator: " + names + " (default ekf)");
  cmd->add_option("--outage-length", a->outage_length, "GNSS outage length (s)");
  cmd->add_option("--outage-period", a->outage_period, "outage start-to-start period (s)");
  cmd->add_option("--outage-start", a->outage_start, "first outage start after the data start (s)");
  cmd->add_option("--config", a->config, "run config YAML (configs/navigate.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--free-inertial", a->free_inertial, "mechanize from the initial state, no GNSS");
  cmd->add_option("--decimate", a->decimate, "write every N-th IMU epoch (default 1)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--lenient", a->lenient, "real-data read policies (repair/warn instead of error)");
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/plot_errors.py");
  cmd->callback([a]() { runNavigate(*a); });
}

}  // namespace graftnav::app
