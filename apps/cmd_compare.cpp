// graftnav compare CASE_DIR --out OUT_DIR [--estimator ekf,rts,fgo] [--imu ref|tested|FILE]
//                  [--outage-length S --outage-period S --outage-start S] [--run-config FILE]
//                  [--start T --end T]
// Runs several estimators on one case and writes a side-by-side table of their outage errors
// (seed: RMS over outage epochs; peers: RMS of per-outage maxima) and of their differences from
// each other (the filter-versus-smoother cross-check), as Markdown and CSV, plus a 1 Hz error
// series for scripts/runtime/plot_compare.py. The runs and the pairs are core/navigate's
// runCompare (streamed when every estimator can stream), the files core/eval's compare report.
//
// Estimators: every name of the estimator table, plus "<name>-noearth" for the graphs (Earth
// rotation off in the preintegration, for the Tang et al. comparison).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/navigate/compare_run.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

struct CompareArgs {
  std::string case_dir, out, imu;
  std::string estimators = "ekf,rts,fgo";
  std::string run_config, profile;
  OutageOverrides outage;  // over the run config's outages: (default 60 s every 180 s from 300 s)
  TimeRangeConfig time_range;  // over the run config's time_range:
  bool no_outages = false;
  bool lenient = false;
  bool no_plots = false;
};

CompareRequest requestOf(const CompareArgs& a) {
  CompareRequest q;
  q.case_dir = a.case_dir;
  q.imu = a.imu;
  q.profile_path = a.profile;
  q.estimators = splitEstimatorList(a.estimators);
  q.run_config = a.run_config;
  q.outage = a.outage;
  q.time_range = a.time_range;
  q.no_outages = a.no_outages;
  q.lenient = a.lenient;
  q.spool_dir = a.out;  // created before the runs
  return q;
}

void runCompareCommand(const CompareArgs& a) {
  if (!a.no_outages) a.outage.validate();
  RunMessages messages;
  messages.on_warning = [](const std::string& w) { fmt::print(stderr, "warning: {}\n", w); };
  messages.on_note = [](const std::string& n) { fmt::print(stderr, "note: {}\n", n); };
  const CompareRequest q = requestOf(a);
  const CompareInputs in = loadCompareInputs(q, estimatorTable(), messages);
  std::filesystem::create_directories(a.out);
  fmt::print(stderr, "compare: {} IMU samples{}, {} GNSS fixes, {} outages of {:.0f} s\n",
             in.imu_samples, in.stream ? " (read in blocks)" : "", in.p.gnss.size(),
             in.p.outages.size(), in.schedule.length_s);
  const CompareReport report = runCompare(q, in, estimatorTable(), [](const CompareRow& r) {
    fmt::print(stderr, "  {:<20s} {:7.2f} s  outage horiz RMS {:.3f} m, GNSS rejected {}\n", r.name,
               r.seconds, r.eval.outage_rms.horizontal_m, r.gnss_rejected);
  });
  int absent = 0;
  const std::string md = writeCompareFiles(report, a.out, &absent);
  fmt::print("{}", md);
  if (absent > 0)
    fmt::print(
        stderr,
        "warning: {} statistics could not be computed (no outage epoch or a zero denominator): "
        "written as '-' in compare.md and empty cells in the CSV files\n",
        absent);
  fmt::print("\nwrote {0}/compare.md, {0}/compare.json, {0}/compare.csv, {0}/compare_errors.csv\n",
             a.out);
  if (a.no_plots) return;
  const std::string w = runPythonScript("plot_compare.py", {a.out});
  if (!w.empty()) fmt::print(stderr, "warning: {}\n", w);
}

}  // namespace

void registerCompare(CLI::App& app) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Run several estimators on one case; table and plot of outage errors and differences");
  cmd->add_option("case_dir", a->case_dir, "case directory")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--estimator", a->estimators,
                  "comma list of " + compareEstimatorNamesText(estimatorTable()))
      ->capture_default_str();
  addDeprecatedOption(cmd, "--estimators", "--estimator", &a->estimators);
  cmd->add_option(
      "--imu", a->imu,
      "ref | tested | FILE (an IMU text file, tested IMU's profile; default: ref, else the "
      "case's only IMU)");
  cmd->add_option("--outage-length", a->outage.length_s,
                  "outage length (s; default: the run config's, else 60)");
  cmd->add_option("--outage-period", a->outage.period_s,
                  "start-to-start spacing (s; default: the run config's, else 180)");
  cmd->add_option("--outage-start", a->outage.start_s,
                  "first outage start after the first IMU epoch (s; default: the run config's, "
                  "else 300)");
  cmd->add_flag("--no-outages", a->no_outages, "use every GNSS fix");
  cmd->add_option("--run-config", a->run_config,
                  "run config YAML (ekf:, fgo:, outages:, time_range: sections; the outage "
                  "and range flags override its sections)")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &a->run_config);
  addTimeRangeOptions(cmd, &a->time_range);
  cmd->add_option("--profile", a->profile, "IMU profile YAML (default: from case.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/runtime/plot_compare.py");
  cmd->add_flag("--lenient", a->lenient, "real-data read policies (repair/warn instead of error)");
  cmd->callback([a]() {
    a->imu = imuChoice(a->imu, a->case_dir);
    runCompareCommand(*a);
  });
}

}  // namespace graftnav::app
