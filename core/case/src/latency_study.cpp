#include "graftnav/case/latency_study.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "graftnav/case/problem.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/eval/real_report.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/nav_io.h"

namespace graftnav {

namespace fs = std::filesystem;

std::optional<Evaluation> evaluateAgainstReference(const NavSolution& sol, const NavSeries& ref,
                                                   const std::vector<TimeWindow>& outages,
                                                   const RunConfig& rc, const StudyLog& log) {
  if (ref.empty()) return std::nullopt;
  try {
    return evaluateSolution(sol, ref, outages, rc.evaluation.options);
  } catch (const std::exception& e) {
    log(fmt::format("warning: evaluation against the reference failed: {}", e.what()));
    return std::nullopt;
  }
}

// The GNSS time-tag latency per fix type: against an RTS track from the track fix types only
// (same initial state, no outages) and against the case's reference solution.
std::string latencyScanMd(const CaseInputs& c, const RunConfig& rc, const EstimationProblem& pr,
                          const LatencyStudyOptions& a, const EstimatorRegistry& estimators,
                          const std::string& out_dir, const StudyLog& log) {
  std::string md;
  // Track from the other fix types only (no outages, RTS), then each RTK type against it and
  // against the reference solution.
  // Same initial state as the main problem (its alignment), GNSS = single-point epochs only.
  GnssSelectionOptions so;
  so.accepted_fix_types = a.track_fix_types;
  so.max_horizontal_std_m = rc.gnss.selection.max_horizontal_std_m;
  so.max_vertical_std_m = rc.gnss.selection.max_vertical_std_m;
  const GnssSelection sel = selectGnss(c.gnss, so);
  log(fmt::format("latency scan: RTS track from the single-point (fix 1) epochs only; {}",
                  sel.counts.summary()));
  EstimationProblem pt = pr;
  pt.gnss = sel.kept;
  pt.outages.clear();
  const NavSolution track = estimators.run("rts", pt, rc);
  writeNav((fs::path(out_dir) / "latency_track_rts_fix1.nav").string(), track.states);
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
  writeFileAtomically((fs::path(out_dir) / "latency_scan.csv").string(), csv);
  return md;
}

// The outage errors with the RTK epochs' time tags corrected by each latency of the grid.
std::string latencyGridMd(const CaseInputs& c, const RunConfig& rc, const ImuSelection& imu,
                          const LatencyStudyOptions& a, const EstimatorRegistry& estimators,
                          const StudyLog& log) {
  std::string md;
  md += "\nEffect of the time-tag correction of the RTK epochs (fix types";
  for (int t : a.grid_fix_types) md += fmt::format(" {}", t);
  md +=
      ") on the outage errors (check points corrected by the same latency).\n\n| latency (s) | estimator | GNSS used / gated | RMS h (m) | RMS of max h (m) | RMS v (m) | vs reference.nav RMS of max h (m) |\n|---|---|---|---|---|---|---|\n";
  for (double L : a.grid) {
    RunConfig rl = rc;
    rl.gnss.given = true;
    for (int t : a.grid_fix_types) rl.gnss.selection.latency_s_by_fix_type[t] = L;
    std::vector<std::string> notes;
    EstimationProblem pl = makeProblem(c, imu, rl, rl.outages, &notes);
    startAtInitialState(&pl, &notes);
    const GnssSeries cps = gnssOfFixTypes(c.gnss, rl.gnss.checkpoint_fix_types, rl.gnss.selection);
    for (const auto& est : a.grid_estimators) {
      const NavSolution s = estimators.run(est, pl, rl);
      const CheckpointEvaluation cp =
          evaluateAtCheckpoints(s.states, cps, pl.outages, pl.lever_arm_b_m);
      const auto ev = evaluateAgainstReference(s, c.reference, pl.outages, rl, log);
      md += fmt::format("| {:.2f} | {} | {} / {} | {:.2f} | {:.2f} | {:.2f} | {} |\n", L, est,
                        s.gnss_used, s.gnss_rejected, cp.rms_h_m, cp.rms_of_max_h_m, cp.rms_v_m,
                        formatOrDash(ev ? ev->outage_max_rms.horizontal_m : std::nan("")));
      log(fmt::format("  latency {:.2f} s, {}: check point RMS h {:.2f} m", L, est, cp.rms_h_m));
    }
  }
  return md;
}

}  // namespace graftnav
