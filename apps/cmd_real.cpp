// graftnav real CASE_DIR --out DIR --config FILE [--imu tested] [--profile FILE]
//   [--estimators ekf,rts,fgo] [--latency-scan] [--latency-grid 0,0.2,0.4] [--latency-types 4,5]
//   Real recordings: one IMU, several estimators, one outage schedule; errors at the withheld
//   GNSS check points (gnss.checkpoint_fix_types of the run config) and against the case's
//   reference solution; optional GNSS time-tag latency scan and the effect of correcting it.
// (`graftnav real-sg` is in cmd_real_sg.cpp.)
// Every reader repair/warning and every GNSS selection count is printed.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/latency_study.h"
#include "graftnav/case/problem.h"
#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/earth.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/eval/real_report.h"
#include "graftnav/sg/grafting.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/estimation/alignment.h"
#include "graftnav/io/provenance.h"
#include "real_case.h"
#include "graftnav/case/run_config.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

void logStderr(const std::string& line) { fmt::print(stderr, "{}\n", line); }

struct RealArgs {
  std::string case_dir, out, run_config, profile, imu;
  std::vector<std::string> estimators{"ekf", "rts", "fgo"};
  bool latency_scan = false;
  LatencyStudyOptions latency;
  bool no_plots = false;
};

// Each estimator on the problem: solution.nav and checkpoints.csv per estimator; a failure is
// printed and listed in *failed, the others go on.
std::vector<EstimatorRun> runEstimators(const RealArgs& a, const CaseInputs& c, const RunConfig& rc,
                                        const EstimationProblem& pr, const GnssSeries& checkpoints,
                                        std::vector<std::string>* failed) {
  std::vector<EstimatorRun> rows;
  for (const auto& est : a.estimators) {
    EstimatorRun r;
    r.label = est;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      r.sol = estimatorTable().run(est, pr, rc);
      for (const auto& st : r.sol.states)
        if (!st.v_n.allFinite() || !std::isfinite(st.pos.lat_rad))
          throw std::runtime_error("non-finite state at t=" + std::to_string(st.t_s));
    } catch (const std::exception& e) {
      fmt::print(stderr, "  {}: FAILED: {}\n", est, e.what());
      failed->push_back(est + ": " + e.what());
      continue;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fs::create_directories(fs::path(a.out) / est);
    writeNav((fs::path(a.out) / est / "solution.nav").string(), r.sol.states);
    r.cp = evaluateAtCheckpoints(r.sol.states, checkpoints, pr.outages, pr.lever_arm_b_m);
    writeCheckpointCsv((fs::path(a.out) / est / "checkpoints.csv").string(), r.cp);
    r.ref = evaluateAgainstReference(r.sol, c.reference, pr.outages, rc, logStderr);
    fmt::print(stderr, "  {}: {:.1f} s, GNSS used {}, rejected by the gate {}, withheld {}\n", est,
               r.seconds, r.sol.gnss_used, r.sol.gnss_rejected, r.sol.gnss_withheld);
    rows.push_back(std::move(r));
  }
  return rows;
}

void runReal(const RealArgs& a) {
  const CaseInputs c = loadReal(a.case_dir);
  std::vector<std::string> warnings;
  const RunConfig rc = loadRunConfig(a.run_config, &warnings);
  recordConfigFile(a.run_config);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!rc.outages_given)
    throw std::runtime_error(a.run_config + ": an outages: section is required");
  const ImuSelection imu = loadImuReal(c, a.imu, a.profile);
  if (!imu.profile_given)
    throw std::runtime_error("no noise parameters for the IMU: pass --profile");
  const EstimationProblem pr = problemReal(c, imu, rc, rc.outages, true);
  const GnssSeries checkpoints =
      gnssOfFixTypes(c.gnss, rc.gnss.checkpoint_fix_types, rc.gnss.selection);
  int checkpoints_in_outages = 0;
  for (const auto& f : checkpoints)
    for (const auto& w : pr.outages) checkpoints_in_outages += w.contains(f.t_s) ? 1 : 0;
  fmt::print(stderr,
             "  {} outages; {} check points inside them (of {} epochs of the fix types in "
             "gnss.checkpoint_fix_types, time tags corrected like the navigation's), lever arm "
             "[{:.2f} {:.2f} {:.2f}] m\n",
             pr.outages.size(), checkpoints_in_outages, checkpoints.size(), pr.lever_arm_b_m.x(),
             pr.lever_arm_b_m.y(), pr.lever_arm_b_m.z());
  fs::create_directories(a.out);
  std::vector<std::string> failed;
  const std::vector<EstimatorRun> rows = runEstimators(a, c, rc, pr, checkpoints, &failed);
  std::string md = realOutageTablesMd(rows, failed, pr.outages, rc.gnss.checkpoint_fix_types,
                                      imu.imu.front().t_s - imu.imu.front().dt_s);
  if (a.latency_scan) md += latencyScanMd(c, rc, pr, a.latency, estimatorTable(), a.out, logStderr);
  if (!a.latency.grid.empty())
    md += latencyGridMd(c, rc, imu, a.latency, estimatorTable(), logStderr);
  writeFileAtomically((fs::path(a.out) / "summary.md").string(), md);
  writeRealSummaryJson((fs::path(a.out) / "summary.json").string(), rows, pr.outages,
                       checkpoints_in_outages, failed);
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
                  "run config YAML (outages:, gnss:, ekf:, fgo:); required")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &a->run_config);
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
