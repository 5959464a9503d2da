// graftnav real CASE_DIR --out DIR --config FILE [--imu tested] [--profile FILE]
//   [--estimators ekf,rts,fgo] [--start T --end T] [--latency-scan] [--latency-grid 0,0.2,0.4]
//   [--latency-types 4,5]
//   Real recordings: one IMU, several estimators, one outage schedule; errors at the withheld
//   GNSS check points (gnss.checkpoint_fix_types of the run config) and against the case's
//   reference solution; optional GNSS time-tag latency scan and the effect of correcting it.
// (`graftnav real-sg` is in cmd_real_sg.cpp.)
// Every reader repair/warning and every GNSS selection count is printed.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/case/latency_study.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/eval/real_report.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/navigate/real_run.h"
#include "graftnav/navigate/real_setup.h"
#include "real_case.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

void logStderr(const std::string& line) { fmt::print(stderr, "{}\n", line); }

struct RealArgs {
  std::string case_dir, out, run_config, profile, imu;
  std::vector<std::string> estimators{"ekf", "rts", "fgo"};
  TimeRangeConfig time_range;  // over the run config's time_range:
  bool latency_scan = false;
  LatencyStudyOptions latency;
  bool no_plots = false;
};

void runReal(const RealArgs& a) {
  RealRequest q;
  q.case_dir = a.case_dir;
  q.run_config = a.run_config;
  q.imu = a.imu;
  q.profile_path = a.profile;
  q.estimators = a.estimators;
  q.time_range = a.time_range;
  q.latency_study = a.latency_scan || !a.latency.grid.empty();
  const RunMessages messages = printedMessages();
  const RealInputs in = loadRealInputs(q, estimatorTable(), messages);
  const EstimationProblem& pr = in.pr;
  fmt::print(stderr,
             "  {} outages; {} check points inside them (of {} epochs of the fix types in "
             "gnss.checkpoint_fix_types, time tags corrected like the navigation's), lever arm "
             "[{:.2f} {:.2f} {:.2f}] m\n",
             pr.outages.size(), in.checkpoints_in_outages, in.checkpoint_epochs,
             pr.lever_arm_b_m.x(), pr.lever_arm_b_m.y(), pr.lever_arm_b_m.z());
  fs::create_directories(a.out);
  std::vector<std::string> failed;
  const std::vector<EstimatorRun> rows =
      runRealEstimators(in, a.estimators, estimatorTable(), a.out, messages, &failed);
  const RunConfig& rc = in.rc;
  std::string md =
      realOutageTablesMd(rows, failed, pr.outages, rc.gnss.checkpoint_fix_types, in.t_first_s);
  if (a.latency_scan)
    md += latencyScanMd(in.c, rc, pr, a.latency, estimatorTable(), a.out, logStderr);
  if (!a.latency.grid.empty())
    md += latencyGridMd(in.c, rc, in.imu, a.latency, estimatorTable(), logStderr);
  writeFileAtomically((fs::path(a.out) / "summary.md").string(), md);
  writeRealSummaryJson((fs::path(a.out) / "summary.json").string(), rows, pr.outages,
                       in.checkpoints_in_outages, failed);
  fmt::print("{}", md);
  fmt::print(
      "wrote {0}/summary.md, {0}/summary.json and per-estimator solution.nav/checkpoints.csv\n",
      a.out);
  if (a.latency_scan && !a.no_plots) {
    const std::string w = runPythonScript(
        "plot_real.py", {"latency", a.out, (fs::path(a.out) / "latency.png").string()});
    if (!w.empty()) fmt::print(stderr, "warning: {}\n", w);
  }
}

}  // namespace

void registerReal(CLI::App& app) {
  auto a = std::make_shared<RealArgs>();
  CLI::App* cmd = app.add_subcommand(
      "real",
      "real recording: estimators, errors at withheld GNSS check points and vs the reference, GNSS latency");
  cmd->add_option("case_dir", a->case_dir, "case directory")->required();
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--run-config", a->run_config,
                  "run config YAML (outages:, gnss:, ekf:, fgo:, time_range:); required; the "
                  "range flags override its time_range:")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &a->run_config);
  addTimeRangeOptions(cmd, &a->time_range);
  cmd->add_option("--imu", a->imu, "ref | tested | FILE (default: ref, else the case's only IMU)");
  cmd->add_option("--profile", a->profile, "IMU profile YAML")->check(CLI::ExistingFile);
  cmd->add_option("--estimator", a->estimators, "comma list of estimators (default ekf,rts,fgo)")
      ->delimiter(',');
  addDeprecatedOption(cmd, "--estimators", "--estimator", &a->estimators);
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/runtime/plot_real.py");
  cmd->add_flag("--latency-scan", a->latency_scan,
                "estimate the GNSS time-tag latency per fix type");
  cmd->add_option("--latency-grid", a->latency.grid,
                  "latencies (s) applied to --latency-types, outage errors for each")
      ->delimiter(',');
  cmd->add_option("--latency-types", a->latency.grid_fix_types,
                  "fix types the latency grid applies to (default 4,5)")
      ->delimiter(',');
  cmd->add_option("--latency-estimators", a->latency.grid_estimators,
                  "estimators of the latency grid (default ekf,rts)")
      ->delimiter(',');
  cmd->callback([a]() {
    requireValue(a->run_config, "--run-config");
    a->imu = imuChoice(a->imu, a->case_dir);
    runReal(*a);
  });
}

}  // namespace graftnav::app
