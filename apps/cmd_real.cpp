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
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/problem.h"
#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/earth.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/eval/gnss_selection.h"
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
constexpr double kR2D = 57.29577951308232;

struct RealArgs {
  std::string case_dir, out, config, profile, imu;
  std::vector<std::string> estimators{"ekf", "rts", "fgo"};
  bool latency_scan = false;
  std::vector<double> latency_grid;
  std::vector<int> latency_types{4, 5};
  std::vector<std::string> latency_estimators{"ekf", "rts"};
  bool no_plots = false;
  // The latency scan's track uses only these fix types (single point: independent of the RTK
  // epochs whose latency is scanned); then each of scan_fix_types is scanned against it, with
  // residuals beyond outlier_m (single point: outlier_single_m) dropped.
  std::vector<int> track_fix_types{1};
  std::vector<int> scan_fix_types{4, 5, 1};
  double outlier_m = 3.0, outlier_single_m = 10.0;
};

struct RunRow {
  std::string label;
  NavSolution sol;
  CheckpointEvaluation cp;
  std::optional<Evaluation> ref;
  double seconds = 0.0;
};

std::optional<Evaluation> evalRef(const NavSolution& sol, const NavSeries& ref,
                                  const std::vector<TimeWindow>& outages, const RunConfig& rc) {
  if (ref.empty()) return std::nullopt;
  try {
    return evaluateSolution(sol, ref, outages, rc.evaluation.options);
  } catch (const std::exception& e) {
    fmt::print(stderr, "warning: evaluation against the reference failed: {}\n", e.what());
    return std::nullopt;
  }
}

std::string fmtOr(double v, const char* f = "{:.2f}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(f), v) : std::string("-");
}

void writeCheckpointCsv(const std::string& path, const CheckpointEvaluation& cp) {
  std::string o = "start_s,end_s,n,rms_h_m,max_h_m,rms_v_m,max_v_m,last_h_m\n";
  for (const auto& w : cp.windows) {
    o += fmt::format("{:.3f},{:.3f},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}\n", w.window.start_s,
                     w.window.end_s, w.n, w.rms_h_m, w.max_h_m, w.rms_v_m, w.max_v_m, w.last_h_m);
  }
  writeFileAtomically(path, o);
}

nlohmann::json numOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// summary.json: the numbers of summary.md's main table, one object per estimator, plus the run's
// provenance (version, commit, command line, config hashes). Angles in degrees; NaN as null.
void writeRealSummaryJson(const std::string& path, const std::vector<RunRow>& rows,
                          const std::vector<TimeWindow>& outages, int checkpoints_in_outages,
                          const std::vector<std::string>& failed) {
  nlohmann::json est = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json e = {
        {"estimator", r.label},
        {"gnss",
         {{"used", r.sol.gnss_used},
          {"rejected", r.sol.gnss_rejected},
          {"withheld", r.sol.gnss_withheld}}},
        {"checkpoints",
         {{"n", r.cp.n},
          {"rms_h_m", numOrNull(r.cp.n ? r.cp.rms_h_m : std::nan(""))},
          {"rms_of_max_h_m", numOrNull(r.cp.n ? r.cp.rms_of_max_h_m : std::nan(""))},
          {"rms_v_m", numOrNull(r.cp.n ? r.cp.rms_v_m : std::nan(""))}}},
        {"run_time_s", r.seconds}};
    if (r.ref) {
      e["reference"] = {{"outage_rms_h_m", numOrNull(r.ref->outage_rms.horizontal_m)},
                        {"outage_max_rms_h_m", numOrNull(r.ref->outage_max_rms.horizontal_m)},
                        {"heading_rms_deg", numOrNull(r.ref->overall_rms.heading_rad * kR2D)}};
    }
    est.push_back(e);
  }
  nlohmann::json w = nlohmann::json::array();
  for (const auto& t : outages) w.push_back({t.start_s, t.end_s});
  const nlohmann::json j = {{"outage_windows_s", w},
                            {"checkpoints_in_outages", checkpoints_in_outages},
                            {"estimators", est},
                            {"failed", failed},
                            {"provenance", provenanceJson()}};
  writeFileAtomically(path, j.dump(2) + "\n");
}

// Each estimator on the problem: solution.nav and checkpoints.csv per estimator; a failure is
// printed and listed in *failed, the others go on.
std::vector<RunRow> runEstimators(const RealArgs& a, const CaseInputs& c, const RunConfig& rc,
                                  const EstimationProblem& pr, const GnssSeries& checkpoints,
                                  std::vector<std::string>* failed) {
  std::vector<RunRow> rows;
  for (const auto& est : a.estimators) {
    RunRow r;
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
    r.ref = evalRef(r.sol, c.reference, pr.outages, rc);
    fmt::print(stderr, "  {}: {:.1f} s, GNSS used {}, rejected by the gate {}, withheld {}\n", est,
               r.seconds, r.sol.gnss_used, r.sol.gnss_rejected, r.sol.gnss_withheld);
    rows.push_back(std::move(r));
  }
  return rows;
}

// summary.md's main table and, per outage, the maximum horizontal error at the check points.
std::string mainTablesMd(const std::vector<RunRow>& rows, const std::vector<std::string>& failed,
                         const EstimationProblem& pr, const RunConfig& rc,
                         const ImuSelection& imu) {
  std::string md;
  md += fmt::format(
      "Outage errors, {} outages of {:.1f} s; check points = withheld GNSS epochs of fix types",
      pr.outages.size(), pr.outages.empty() ? 0.0 : pr.outages.front().length_s());
  for (int t : rc.gnss.checkpoint_fix_types) md += fmt::format(" {}", t);
  md += " inside the outages.\n\n";
  md +=
      "| estimator | GNSS used / gated / withheld | check points | RMS h (m) | RMS of per-outage max h (m) | RMS v (m) | vs reference.nav: outage RMS h (m) | RMS of max h (m) | heading RMS (deg) | run (s) |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const double nan = std::nan("");
    md += fmt::format("| {} | {} / {} / {} | {} | {} | {} | {} | {} | {} | {} | {:.1f} |\n",
                      r.label, r.sol.gnss_used, r.sol.gnss_rejected, r.sol.gnss_withheld, r.cp.n,
                      fmtOr(r.cp.n ? r.cp.rms_h_m : nan), fmtOr(r.cp.n ? r.cp.rms_of_max_h_m : nan),
                      fmtOr(r.cp.n ? r.cp.rms_v_m : nan),
                      fmtOr(r.ref ? r.ref->outage_rms.horizontal_m : nan),
                      fmtOr(r.ref ? r.ref->outage_max_rms.horizontal_m : nan),
                      fmtOr(r.ref ? r.ref->overall_rms.heading_rad * kR2D : nan), r.seconds);
  }
  for (const auto& f : failed) md += "\nFAILED " + f + "\n";
  // Per outage, per estimator: max horizontal error at the check points.
  if (!rows.empty() && !rows.front().cp.windows.empty()) {
    md +=
        "\nPer outage: maximum horizontal error at the check points (m), number of check points\n\n| outage (s after start) | n |";
    for (const auto& r : rows) md += " " + r.label + " |";
    md += "\n|---|---|";
    for (std::size_t i = 0; i < rows.size(); ++i) md += "---|";
    md += "\n";
    const double t_first = imu.imu.front().t_s - imu.imu.front().dt_s;
    for (std::size_t w = 0; w < rows.front().cp.windows.size(); ++w) {
      const auto& win = rows.front().cp.windows[w];
      md += fmt::format("| {:.0f}-{:.0f} | {} |", win.window.start_s - t_first,
                        win.window.end_s - t_first, win.n);
      for (const auto& r : rows)
        md += w < r.cp.windows.size() ? fmt::format(" {:.2f} |", r.cp.windows[w].max_h_m) : " - |";
      md += "\n";
    }
  }
  return md;
}

// The GNSS time-tag latency per fix type: against an RTS track from the track fix types only
// (same initial state, no outages) and against the case's reference solution.
std::string latencyScanMd(const RealArgs& a, const CaseInputs& c, const RunConfig& rc,
                          const EstimationProblem& pr) {
  std::string md;
  // Track from the other fix types only (no outages, RTS), then each RTK type against it and
  // against the reference solution.
  // Same initial state as the main problem (its alignment), GNSS = single-point epochs only.
  GnssSelectionOptions so;
  so.accepted_fix_types = a.track_fix_types;
  so.max_horizontal_std_m = rc.gnss.selection.max_horizontal_std_m;
  so.max_vertical_std_m = rc.gnss.selection.max_vertical_std_m;
  const GnssSelection sel = selectGnss(c.gnss, so);
  fmt::print(stderr, "latency scan: RTS track from the single-point (fix 1) epochs only; {}\n",
             sel.counts.summary());
  EstimationProblem pt = pr;
  pt.gnss = sel.kept;
  pt.outages.clear();
  const NavSolution track = estimatorTable().run("rts", pt, rc);
  writeNav((fs::path(a.out) / "latency_track_rts_fix1.nav").string(), track.states);
  md +=
      "\nGNSS time-tag latency (tau > 0: the fix is the position tau seconds BEFORE its stamp); "
      "grid = minimum of the horizontal residual RMS over shifts, slope = along-track least squares.\n\n";
  md +=
      "| fix type | track | fixes used (slow, outliers) | tau grid (s) | tau slope (s) | RMS h at 0 (m) | RMS h at tau (m) |\n|---|---|---|---|---|---|---|\n";
  std::string csv = "fix_type,track,shift_s,rms_h_m\n";
  struct Track {
    std::string name;
    const NavSeries* s;
  };
  const std::vector<Track> tracks = {{"RTS(fix 1 only)", &track.states},
                                     {"reference.nav", &c.reference}};
  for (int ft : a.scan_fix_types) {
    const GnssSeries fixes = gnssOfFixTypes(c.gnss, {ft}, GnssSelectionOptions{});
    for (const auto& tr : tracks) {
      if (tr.s->empty() || (ft == 1 && tr.s == &track.states)) continue;
      try {
        LatencyScanOptions lo;
        lo.outlier_m = ft == 1 ? a.outlier_single_m : a.outlier_m;
        const LatencyEstimate e = estimateGnssLatency(*tr.s, fixes, pr.lever_arm_b_m, lo);
        md += fmt::format("| {} | {} | {} ({}, {}) | {:+.3f} | {:+.3f} | {:.2f} | {:.2f} |\n", ft,
                          tr.name, e.fixes_used, e.fixes_slow, e.fixes_outliers, e.grid_s,
                          e.slope_s, e.rms_h_at_zero_m, e.grid_rms_h_m);
        for (std::size_t i = 0; i < e.shift_s.size(); ++i)
          csv += fmt::format("{},{},{:.3f},{:.4f}\n", ft, tr.name, e.shift_s[i], e.rms_h_m[i]);
      } catch (const std::exception& ex) {
        md += fmt::format("| {} | {} | not estimated: {} | | | | |\n", ft, tr.name, ex.what());
      }
    }
  }
  writeFileAtomically((fs::path(a.out) / "latency_scan.csv").string(), csv);
  return md;
}

// The outage errors with the RTK epochs' time tags corrected by each latency of the grid.
std::string latencyGridMd(const RealArgs& a, const CaseInputs& c, const RunConfig& rc,
                          const ImuSelection& imu) {
  std::string md;
  md += "\nEffect of the time-tag correction of the RTK epochs (fix types";
  for (int t : a.latency_types) md += fmt::format(" {}", t);
  md +=
      ") on the outage errors (check points corrected by the same latency).\n\n| latency (s) | estimator | GNSS used / gated | RMS h (m) | RMS of max h (m) | RMS v (m) | vs reference.nav RMS of max h (m) |\n|---|---|---|---|---|---|---|\n";
  for (double L : a.latency_grid) {
    RunConfig rl = rc;
    rl.gnss.given = true;
    for (int t : a.latency_types) rl.gnss.selection.latency_s_by_fix_type[t] = L;
    const EstimationProblem pl = problemReal(c, imu, rl, rl.outages, false);
    const GnssSeries cps = gnssOfFixTypes(c.gnss, rl.gnss.checkpoint_fix_types, rl.gnss.selection);
    for (const auto& est : a.latency_estimators) {
      const NavSolution s = estimatorTable().run(est, pl, rl);
      const CheckpointEvaluation cp =
          evaluateAtCheckpoints(s.states, cps, pl.outages, pl.lever_arm_b_m);
      const auto ev = evalRef(s, c.reference, pl.outages, rl);
      md += fmt::format("| {:.2f} | {} | {} / {} | {:.2f} | {:.2f} | {:.2f} | {} |\n", L, est,
                        s.gnss_used, s.gnss_rejected, cp.rms_h_m, cp.rms_of_max_h_m, cp.rms_v_m,
                        fmtOr(ev ? ev->outage_max_rms.horizontal_m : std::nan("")));
      fmt::print(stderr, "  latency {:.2f} s, {}: check-point RMS h {:.2f} m\n", L, est,
                 cp.rms_h_m);
    }
  }
  return md;
}

void runReal(const RealArgs& a) {
  const CaseInputs c = loadReal(a.case_dir);
  std::vector<std::string> warnings;
  const RunConfig rc = loadRunConfig(a.config, &warnings);
  recordConfigFile(a.config);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!rc.outages_given) throw std::runtime_error(a.config + ": an outages: section is required");
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
  const std::vector<RunRow> rows = runEstimators(a, c, rc, pr, checkpoints, &failed);
  std::string md = mainTablesMd(rows, failed, pr, rc, imu);
  if (a.latency_scan) md += latencyScanMd(a, c, rc, pr);
  if (!a.latency_grid.empty()) md += latencyGridMd(a, c, rc, imu);
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
  cmd->add_option("--run-config", a->config,
                  "run config YAML (outages:, gnss:, ekf:, fgo:); required")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &a->config);
  cmd->add_option("--imu", a->imu, "ref | tested | FILE (default: ref, else the case's only IMU)");
  cmd->add_option("--profile", a->profile, "IMU profile YAML")->check(CLI::ExistingFile);
  cmd->add_option("--estimator", a->estimators, "comma list of estimators (default ekf,rts,fgo)")
      ->delimiter(',');
  addDeprecatedOption(cmd, "--estimators", "--estimator", &a->estimators);
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/runtime/plot_real.py");
  cmd->add_flag("--latency-scan", a->latency_scan,
                "estimate the GNSS time-tag latency per fix type");
  cmd->add_option("--latency-grid", a->latency_grid,
                  "latencies (s) applied to --latency-types, outage errors for each")
      ->delimiter(',');
  cmd->add_option("--latency-types", a->latency_types,
                  "fix types the latency grid applies to (default 4,5)")
      ->delimiter(',');
  cmd->add_option("--latency-estimators", a->latency_estimators,
                  "estimators of the latency grid (default ekf,rts)")
      ->delimiter(',');
  cmd->callback([a]() {
    requireValue(a->config, "--run-config");
    a->imu = imuChoice(a->imu, a->case_dir);
    runReal(*a);
  });
}

}  // namespace graftnav::app
