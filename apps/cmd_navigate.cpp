// graftnav navigate CASE_DIR --out OUT_DIR [--imu ref|tested|FILE] [--profile FILE]
//   [--estimator ekf,rts,...] [--outage-length S --outage-period S --outage-start S]
//   [--run-config FILE] [--start T --end T] [--decimate N] [--lenient] [--no-plots]
// Several estimators write OUT_DIR/<estimator>/. Without --run-config, CASE_DIR/run.yaml is used
// when present (written by `graftnav import`). The run itself is core/navigate: estimators with a
// streamed form read the IMU in blocks and write their per-epoch files as they go.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/navigate/navigate_run.h"
#include "graftnav/navigate/navigate_setup.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

struct NavigateArgs {
  std::string case_dir, out, imu, profile, estimator = "ekf", run_config;
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

// The command line as a run request: every path resolved against the case, then the working
// directory.
NavigateRequest requestOf(const NavigateArgs& a, const std::string& estimator) {
  NavigateRequest q;
  q.case_dir = a.case_dir;
  q.out_dir = a.out;
  q.imu =
      a.imu == "ref" || a.imu == "tested" ? a.imu : resolveUserPath(a.imu, a.case_dir, "IMU file");
  if (!a.profile.empty()) q.profile_path = resolveUserPath(a.profile, a.case_dir, "IMU profile");
  q.estimator = estimator;
  q.run_config = runConfigPathFor(a.run_config, a.case_dir);
  q.run_config_from_case = a.run_config.empty() && !q.run_config.empty();
  q.outage = a.outage;
  q.time_range = a.time_range;
  q.decimate = a.decimate;
  q.lenient = a.lenient;
  return q;
}

void runNavigateOne(const NavigateArgs& a, const NavigateRequest& q) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  RunMessages messages;
  messages.on_warning = [](const std::string& w) { fmt::print(stderr, "warning: {}\n", w); };
  messages.on_note = [](const std::string& n) { fmt::print(stderr, "note: {}\n", n); };
  fmt::print(stderr, "[{:6.1f} s] reading the case and the {} IMU\n", elapsed(), a.imu);
  const NavigateSetup s = prepareNavigate(q, estimatorTable(), messages);
  // Created before the run so that an unusable --out fails now, not after the filter.
  fs::create_directories(q.out_dir);
  if (s.stream) {
    fmt::print(stderr,
               "[{:6.1f} s] streaming the {} IMU: {} on {} in blocks, {} GNSS fixes, {} outages\n",
               elapsed(), a.imu, s.estimator, s.imu.path, s.gnss_count, s.pr.outages.size());
  } else {
    fmt::print(stderr, "[{:6.1f} s] {} on {} IMU samples, {} GNSS fixes, {} outages\n", elapsed(),
               s.estimator, s.pr.imu.size(), s.gnss_count, s.pr.outages.size());
  }
  int last_decile = -1;
  const ProgressFn progress = [&](double f) {
    const int d = static_cast<int>(f * 10.0);
    if (d != last_decile) {
      last_decile = d;
      fmt::print(stderr, "[{:6.1f} s] {} {:3d} %\n", elapsed(), s.estimator, d * 10);
    }
  };
  const NavigateOutcome o = runNavigate(s, q.out_dir, estimatorTable(), messages, progress);
  fmt::print("{}: {} epochs -> {} ({:.2f} s)\n", s.estimator, o.files.epochs,
             (fs::path(q.out_dir) / "solution.nav").string(), o.run_time_s);
  if (o.files.imu_errors) fmt::print("  wrote imu_errors.txt\n");
  if (o.files.state_std) fmt::print("  wrote state_std.txt\n");
  if (s.uses_gnss) {
    fmt::print("  GNSS used {}, rejected by the gate {}, withheld in outages {}\n",
               o.solution.gnss_used, o.solution.gnss_rejected, o.solution.gnss_withheld);
  }
  if (!o.evaluation) {
    fmt::print(
        "  no field/truth.nav or reference solution: no errors written (run_info.json only)\n");
    return;
  }
  printEvaluation(*o.evaluation);
  fmt::print("  wrote errors.json, run_info.json, errors.csv, outage_drift.csv in {}\n", q.out_dir);
  if (a.no_plots) return;
  const std::string w = runPythonScript("plot_errors.py", {q.out_dir});
  if (!w.empty()) {
    fmt::print(stderr, "warning: {}\n", w);
  } else {
    fmt::print("  wrote error plots (errors_*.png) in {}\n", q.out_dir);
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
    NavigateRequest q = requestOf(a, e);
    if (estimators.size() > 1) q.out_dir = (fs::path(a.out) / e).string();
    runNavigateOne(a, q);
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
  cmd->add_option("--run-config", a->run_config,
                  "run config YAML (configs/navigate.yaml; default CASE/run.yaml)");
  addDeprecatedOption(cmd, "--config", "--run-config", &a->run_config);
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
