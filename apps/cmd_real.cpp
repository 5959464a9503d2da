// graftnav real CASE_DIR --out DIR --config FILE [--imu tested] [--profile FILE]
//   [--estimators ekf,rts,fgo] [--latency-scan] [--latency-grid 0,0.2,0.4] [--latency-types 4,5]
//   Real recordings: one IMU, several estimators, one outage schedule; errors at the withheld
//   GNSS check points (gnss.checkpoint_fix_types of the run config) and against the case's
//   reference solution; optional GNSS time-tag latency scan and the effect of correcting it.
// graftnav real-sg CASE_DIR --out DIR --config FILE --ref-profile FILE --tested-profile FILE
//   Real-data signal grafting: the tested IMU's basic errors from its own standstill spans,
//   grafted onto the reference IMU (SG#1), navigated next to the real tested IMU and the
//   reference IMU; ERR against SOL_REF (reference IMU, smoothed, all GNSS) and DIFF = SG - REAL.
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

#include "case_loader.h"
#include "cli_vocabulary.h"
#include "commands.h"
#include "estimators.h"
#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/earth.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/sg/grafting.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/filters/alignment.h"
#include "provenance.h"
#include "run_config.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;
constexpr double kR2D = 57.29577951308232;

struct RealArgs {
  std::string case_dir, out, config, profile, imu = kDefaultImu;
  std::vector<std::string> estimators{"ekf", "rts", "fgo"};
  bool latency_scan = false;
  std::vector<double> latency_grid;
  std::vector<int> latency_types{4, 5};
  std::vector<std::string> latency_estimators{"ekf", "rts"};
  bool no_plots = false;
};

void printLines(const std::string& prefix, const std::string& text) {
  if (text.empty()) return;
  std::size_t a = 0;
  while (a < text.size()) {
    std::size_t b = text.find('\n', a);
    if (b == std::string::npos) b = text.size();
    fmt::print(stderr, "{}{}\n", prefix, text.substr(a, b - a));
    a = b + 1;
  }
}

// Loads the case (real read policies) and prints every reader condition.
CaseInputs loadReal(const std::string& dir) {
  CaseLoadOptions lo;
  lo.lenient = true;
  CaseInputs c = loadCaseInputs(dir, lo);
  fmt::print(stderr, "read {} (real read policies): {} GNSS epochs, reference {} ({} epochs)\n", dir,
             c.gnss.size(), c.reference_name.empty() ? "none" : c.reference_name, c.reference.size());
  if (c.warnings.empty()) fmt::print(stderr, "  readers: no repair and no warning\n");
  for (const auto& w : c.warnings) printLines("  reader/case: ", w);
  return c;
}

ImuSelection loadImuReal(const CaseInputs& c, const std::string& which, const std::string& profile) {
  ImuSelection s = selectImu(c, which, profile, true);
  fmt::print(stderr, "IMU '{}' {}: {} samples, profile '{}'\n", which, s.path, s.imu.size(), s.label);
  if (s.read_summary.empty()) {
    fmt::print(stderr, "  reader: no repair and no warning\n");
  } else {
    printLines("  reader: ", s.read_summary);
  }
  return s;
}

EstimationProblem problemReal(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                              bool with_outages, bool verbose) {
  std::vector<std::string> notes;
  std::optional<OutageScheduleConfig> oc;
  if (with_outages) oc = rc.outages;
  EstimationProblem pr = makeProblem(c, imu, rc, oc, &notes);
  // Start the IMU series at the initial state's epoch (after an alignment): every estimator then
  // starts from the same state at the same sample (the graph integrates from the first sample).
  const double t_init = pr.initial.t_s;
  std::size_t k0 = 0;
  while (k0 < pr.imu.size() && pr.imu[k0].t_s - pr.imu[k0].dt_s < t_init - 1e-6) ++k0;
  if (k0 > 0 && k0 < pr.imu.size()) {
    pr.imu.erase(pr.imu.begin(), pr.imu.begin() + static_cast<std::ptrdiff_t>(k0));
    notes.push_back(fmt::format("IMU series starts at the initial state epoch t={:.3f} ({} earlier samples "
                                "used only by the alignment)", t_init, k0));
  }
  // GNSS epochs before the start are not navigation inputs (the EKF skips them; the graph would
  // anchor nodes where no IMU data connects them).
  const auto first_gnss = std::find_if(pr.gnss.begin(), pr.gnss.end(),
                                       [&](const GnssFix& f) { return f.t_s > t_init + 1e-6; });
  if (first_gnss != pr.gnss.begin()) {
    notes.push_back(fmt::format("{} GNSS epochs before the initial state epoch not used",
                                std::distance(pr.gnss.begin(), first_gnss)));
    pr.gnss.erase(pr.gnss.begin(), first_gnss);
  }
  if (verbose) {
    for (const auto& n : notes) fmt::print(stderr, "  note: {}\n", n);
    if (rc.alignment.mode == "static" && c.config.initial_state) {
      const double yaw_case = eulerFromQuat(c.config.initial_state->q_nb).z() * kR2D;
      const double yaw_used = eulerFromQuat(pr.initial.q_nb).z() * kR2D;
      const double d = std::remainder(yaw_used - yaw_case, 360.0);
      fmt::print(stderr,
                 "  {}: {} alignment from the data: yaw {:.1f} deg at t={:.3f} (case.yaml initial_state: "
                 "{:.1f} deg at t={:.3f}; difference {:.1f} deg{})\n",
                 std::abs(d) > 5.0 ? "WARNING" : "note", rc.alignment.mode, yaw_used, pr.initial.t_s,
                 yaw_case, c.config.initial_state->t_s, d,
                 std::abs(d) > 5.0 ? ": the case's initial heading is NOT used" : "");
    }
  }
  return pr;
}

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

nlohmann::json numOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// summary.json: the numbers of summary.md's main table, one object per estimator, plus the run's
// provenance (version, commit, command line, config hashes). Angles in degrees; NaN as null.
void writeRealSummaryJson(const std::string& path, const std::vector<RunRow>& rows,
                          const std::vector<TimeWindow>& outages, int checkpoints_in_outages,
                          const std::vector<std::string>& failed) {
  nlohmann::json est = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json e = {{"estimator", r.label},
                        {"gnss", {{"used", r.sol.gnss_used}, {"rejected", r.sol.gnss_rejected},
                                  {"withheld", r.sol.gnss_withheld}}},
                        {"checkpoints", {{"n", r.cp.n},
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
  const nlohmann::json j = {{"outage_windows_s", w}, {"checkpoints_in_outages", checkpoints_in_outages},
                            {"estimators", est}, {"failed", failed}, {"provenance", provenanceJson()}};
  writeFileAtomically(path, j.dump(2) + "\n");
}

void runReal(const RealArgs& a) {
  const CaseInputs c = loadReal(a.case_dir);
  std::vector<std::string> warnings;
  const RunConfig rc = loadRunConfig(a.config, &warnings);
  recordConfigFile(a.config);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!rc.outages_given) throw std::runtime_error(a.config + ": an outages: section is required");
  const ImuSelection imu = loadImuReal(c, a.imu, a.profile);
  if (!imu.profile_given) throw std::runtime_error("no noise parameters for the IMU: pass --profile");
  const EstimationProblem pr = problemReal(c, imu, rc, true, true);
  const GnssSeries checkpoints =
      gnssOfFixTypes(c.gnss, rc.gnss.checkpoint_fix_types, rc.gnss.selection);
  int checkpoints_in_outages = 0;
  for (const auto& f : checkpoints)
    for (const auto& w : pr.outages) checkpoints_in_outages += w.contains(f.t_s) ? 1 : 0;
  fmt::print(stderr, "  {} outages; {} check points inside them (of {} epochs of the fix types in "
             "gnss.checkpoint_fix_types, time tags corrected like the navigation's), lever arm "
             "[{:.2f} {:.2f} {:.2f}] m\n",
             pr.outages.size(), checkpoints_in_outages, checkpoints.size(), pr.lever_arm_b_m.x(),
             pr.lever_arm_b_m.y(), pr.lever_arm_b_m.z());
  fs::create_directories(a.out);
  std::vector<RunRow> rows;
  std::vector<std::string> failed;
  for (const auto& est : a.estimators) {
    RunRow r;
    r.label = est;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      r.sol = runEstimator(est, pr, rc);
      for (const auto& st : r.sol.states)
        if (!st.v_n.allFinite() || !std::isfinite(st.pos.lat_rad)) throw std::runtime_error("non-finite state at t=" + std::to_string(st.t_s));
    } catch (const std::exception& e) {
      fmt::print(stderr, "  {}: FAILED: {}\n", est, e.what());
      failed.push_back(est + ": " + e.what());
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
  std::string md;
  md += fmt::format("Outage errors, {} outages of {:.1f} s; check points = withheld GNSS epochs of fix types",
                    pr.outages.size(), pr.outages.empty() ? 0.0 : pr.outages.front().length_s());
  for (int t : rc.gnss.checkpoint_fix_types) md += fmt::format(" {}", t);
  md += " inside the outages.\n\n";
  md += "| estimator | GNSS used / gated / withheld | check points | RMS h (m) | RMS of per-outage max h (m) | RMS v (m) | vs reference.nav: outage RMS h (m) | RMS of max h (m) | heading RMS (deg) | run (s) |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const double nan = std::nan("");
    md += fmt::format("| {} | {} / {} / {} | {} | {} | {} | {} | {} | {} | {} | {:.1f} |\n", r.label,
                      r.sol.gnss_used, r.sol.gnss_rejected, r.sol.gnss_withheld, r.cp.n,
                      fmtOr(r.cp.n ? r.cp.rms_h_m : nan), fmtOr(r.cp.n ? r.cp.rms_of_max_h_m : nan),
                      fmtOr(r.cp.n ? r.cp.rms_v_m : nan),
                      fmtOr(r.ref ? r.ref->outage_rms.horizontal_m : nan),
                      fmtOr(r.ref ? r.ref->outage_max_rms.horizontal_m : nan),
                      fmtOr(r.ref ? r.ref->overall_rms.heading_rad * kR2D : nan), r.seconds);
  }
  for (const auto& f : failed) md += "\nFAILED " + f + "\n";
  // Per outage, per estimator: max horizontal error at the check points.
  if (!rows.empty() && !rows.front().cp.windows.empty()) {
    md += "\nPer outage: maximum horizontal error at the check points (m), number of check points\n\n| outage (s after start) | n |";
    for (const auto& r : rows) md += " " + r.label + " |";
    md += "\n|---|---|";
    for (std::size_t i = 0; i < rows.size(); ++i) md += "---|";
    md += "\n";
    const double t_first = imu.imu.front().t_s - imu.imu.front().dt_s;
    for (std::size_t w = 0; w < rows.front().cp.windows.size(); ++w) {
      const auto& win = rows.front().cp.windows[w];
      md += fmt::format("| {:.0f}-{:.0f} | {} |", win.window.start_s - t_first, win.window.end_s - t_first, win.n);
      for (const auto& r : rows) md += w < r.cp.windows.size() ? fmt::format(" {:.2f} |", r.cp.windows[w].max_h_m) : " - |";
      md += "\n";
    }
  }

  if (a.latency_scan) {
    // Track from the other fix types only (no outages, RTS), then each RTK type against it and
    // against the reference solution.
    // Same initial state as the main problem (its alignment), GNSS = single-point epochs only.
    GnssSelectionOptions so;
    so.accepted_fix_types = {1};
    so.max_horizontal_std_m = rc.gnss.selection.max_horizontal_std_m;
    so.max_vertical_std_m = rc.gnss.selection.max_vertical_std_m;
    const GnssSelection sel = selectGnss(c.gnss, so);
    fmt::print(stderr, "latency scan: RTS track from the single-point (fix 1) epochs only; {}\n", sel.counts.summary());
    EstimationProblem pt = pr;
    pt.gnss = sel.kept;
    pt.outages.clear();
    const NavSolution track = runEstimator("rts", pt, rc);
    writeNav((fs::path(a.out) / "latency_track_rts_fix1.nav").string(), track.states);
    md += "\nGNSS time-tag latency (tau > 0: the fix is the position tau seconds BEFORE its stamp); "
          "grid = minimum of the horizontal residual RMS over shifts, slope = along-track least squares.\n\n";
    md += "| fix type | track | fixes used (slow, outliers) | tau grid (s) | tau slope (s) | RMS h at 0 (m) | RMS h at tau (m) |\n|---|---|---|---|---|---|---|\n";
    std::string csv = "fix_type,track,shift_s,rms_h_m\n";
    struct Track { std::string name; const NavSeries* s; };
    const std::vector<Track> tracks = {{"RTS(fix 1 only)", &track.states}, {"reference.nav", &c.reference}};
    for (int ft : {4, 5, 1}) {
      const GnssSeries fixes = gnssOfFixTypes(c.gnss, {ft}, GnssSelectionOptions{});
      for (const auto& tr : tracks) {
        if (tr.s->empty() || (ft == 1 && tr.s == &track.states)) continue;
        try {
          LatencyScanOptions lo;
          lo.outlier_m = ft == 1 ? 10.0 : 3.0;
          const LatencyEstimate e = estimateGnssLatency(*tr.s, fixes, pr.lever_arm_b_m, lo);
          md += fmt::format("| {} | {} | {} ({}, {}) | {:+.3f} | {:+.3f} | {:.2f} | {:.2f} |\n", ft, tr.name,
                            e.fixes_used, e.fixes_slow, e.fixes_outliers, e.grid_s, e.slope_s,
                            e.rms_h_at_zero_m, e.grid_rms_h_m);
          for (std::size_t i = 0; i < e.shift_s.size(); ++i)
            csv += fmt::format("{},{},{:.3f},{:.4f}\n", ft, tr.name, e.shift_s[i], e.rms_h_m[i]);
        } catch (const std::exception& ex) {
          md += fmt::format("| {} | {} | not estimated: {} | | | | |\n", ft, tr.name, ex.what());
        }
      }
    }
    writeFileAtomically((fs::path(a.out) / "latency_scan.csv").string(), csv);
  }

  if (!a.latency_grid.empty()) {
    md += "\nEffect of the time-tag correction of the RTK epochs (fix types";
    for (int t : a.latency_types) md += fmt::format(" {}", t);
    md += ") on the outage errors (check points corrected by the same latency).\n\n| latency (s) | estimator | GNSS used / gated | RMS h (m) | RMS of max h (m) | RMS v (m) | vs reference.nav RMS of max h (m) |\n|---|---|---|---|---|---|---|\n";
    for (double L : a.latency_grid) {
      RunConfig rl = rc;
      rl.gnss.given = true;
      for (int t : a.latency_types) rl.gnss.selection.latency_s_by_fix_type[t] = L;
      const EstimationProblem pl = problemReal(c, imu, rl, true, false);
      const GnssSeries cps = gnssOfFixTypes(c.gnss, rl.gnss.checkpoint_fix_types, rl.gnss.selection);
      for (const auto& est : a.latency_estimators) {
        const NavSolution s = runEstimator(est, pl, rl);
        const CheckpointEvaluation cp = evaluateAtCheckpoints(s.states, cps, pl.outages, pl.lever_arm_b_m);
        const auto ev = evalRef(s, c.reference, pl.outages, rl);
        md += fmt::format("| {:.2f} | {} | {} / {} | {:.2f} | {:.2f} | {:.2f} | {} |\n", L, est, s.gnss_used,
                          s.gnss_rejected, cp.rms_h_m, cp.rms_of_max_h_m, cp.rms_v_m,
                          fmtOr(ev ? ev->outage_max_rms.horizontal_m : std::nan("")));
        fmt::print(stderr, "  latency {:.2f} s, {}: check-point RMS h {:.2f} m\n", L, est, cp.rms_h_m);
      }
    }
  }
  writeFileAtomically((fs::path(a.out) / "summary.md").string(), md);
  writeRealSummaryJson((fs::path(a.out) / "summary.json").string(), rows, pr.outages, checkpoints_in_outages,
                       failed);
  fmt::print("{}", md);
  fmt::print("wrote {0}/summary.md, {0}/summary.json and per-estimator solution.nav/checkpoints.csv\n", a.out);
  if (a.latency_scan && !a.no_plots) {
    const std::string w = runPythonScript("real_plots.py", {"latency", a.out, (fs::path(a.out) / "latency.png").string()});
    if (!w.empty()) fmt::print(stderr, "warning: {}\n", w);
  }
}

// ---------------------------------------------------------------------------------------------
// real-sg

struct RealSgArgs {
  std::string case_dir, out, config, ref_profile, tested_profile, estimator = "rts";
  std::uint64_t seed = 1;
  double detector_gyro_rad_s = 0.05, detector_accel_m_s2 = 0.3, min_static_s = 2.0;
  double max_static_speed_m_s = 0.3;
  bool no_plots = false;  // real-sg writes no plots; accepted for one vocabulary
};

// Basic error increments of `imu` over its standstill spans: measured minus the theoretical
// output at rest (gravity along the span's own mean specific-force direction with the normal
// gravity magnitude; Earth rate in the levelled body frame with heading yaw_rad). The levelled
// direction absorbs the horizontal accelerometer bias into the tilt, as an alignment would.
ImuSeries staticErrorIncrements(const ImuSeries& imu, const std::vector<StaticInterval>& spans,
                                const Geodetic& pos, double yaw_rad) {
  ImuSeries err;
  double t = 0.0;
  const double g = earth::gravityMagnitude(pos);
  for (const auto& sp : spans) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    double T = 0.0;
    for (std::size_t k = sp.begin; k < sp.end; ++k) {
      f += imu[k].dvel_m_s;
      T += imu[k].dt_s;
    }
    f /= T;
    const Eigen::Vector3d f_th = f.normalized() * g;
    const Eigen::Vector2d rp = levelFromSpecificForce(f);
    const Eigen::Matrix3d C_nb = quatFromEuler(Eigen::Vector3d(rp.x(), rp.y(), yaw_rad)).toRotationMatrix();
    const Eigen::Vector3d w_th = C_nb.transpose() * earth::omega_ie_n(pos.lat_rad);
    for (std::size_t k = sp.begin; k < sp.end; ++k) {
      ImuSample s = imu[k];
      t += s.dt_s;
      s.t_s = t;
      s.dtheta_rad -= w_th * s.dt_s;
      s.dvel_m_s -= f_th * s.dt_s;
      err.push_back(s);
    }
  }
  return err;
}

void runRealSg(const RealSgArgs& a) {
  const CaseInputs c = loadReal(a.case_dir);
  std::vector<std::string> warnings;
  const RunConfig rc = loadRunConfig(a.config, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!rc.outages_given) throw std::runtime_error(a.config + ": an outages: section is required");
  const ImuSelection ref = loadImuReal(c, "ref", a.ref_profile);
  const ImuSelection tested = loadImuReal(c, "tested", a.tested_profile);
  fs::create_directories(a.out);

  // SOL_REF: the reference IMU, smoothed, with every selected GNSS epoch.
  fmt::print(stderr, "SOL_REF: reference IMU, {}, no outages\n", "rts");
  const EstimationProblem p_ref_full = problemReal(c, ref, rc, false, true);
  const NavSolution sol_ref = runEstimator("rts", p_ref_full, rc);
  writeNav((fs::path(a.out) / "sol_ref.nav").string(), sol_ref.states);

  // Standstill spans of the tested IMU -> basic error signal.
  StaticDetectorOptions so;
  so.gyro_threshold_rad_s = a.detector_gyro_rad_s;
  so.accel_threshold_m_s2 = a.detector_accel_m_s2;
  so.min_duration_s = a.min_static_s;
  so.trim_s = 0.5;
  const StaticDetection det = detectStaticIntervals(tested.imu, so);
  // Keep only spans during which the GNSS positions show a standstill (a smooth constant-speed
  // drive can pass the variance test too).
  std::vector<StaticInterval> spans;
  int moving_spans = 0;
  for (const auto& sp : det.intervals) {
    // Median speed over >= 1-s chords between fixes inside the span (robust to position blips).
    std::vector<double> speeds;
    for (std::size_t i = 0; i < c.gnss.size(); ++i) {
      if (c.gnss[i].t_s < sp.t_begin_s) continue;
      std::size_t j = i + 1;
      while (j < c.gnss.size() && c.gnss[j].t_s - c.gnss[i].t_s < 1.0) ++j;
      if (j >= c.gnss.size() || c.gnss[j].t_s > sp.t_end_s) break;
      speeds.push_back(earth::nedFromGeodetic(c.gnss[i].pos, c.gnss[j].pos).head<2>().norm() /
                       (c.gnss[j].t_s - c.gnss[i].t_s));
    }
    double vmax = 0.0;  // median chord speed
    if (!speeds.empty()) {
      std::nth_element(speeds.begin(), speeds.begin() + speeds.size() / 2, speeds.end());
      vmax = speeds[speeds.size() / 2];
    }
    if (vmax > a.max_static_speed_m_s) {
      ++moving_spans;
    } else {
      spans.push_back(sp);
    }
  }
  fmt::print(stderr, "static detector: {} spans, {} dropped because the median GNSS speed inside exceeds {:.2f} m/s\n",
             det.intervals.size(), moving_spans, a.max_static_speed_m_s);
  if (spans.empty()) throw std::runtime_error("no standstill span found in the tested IMU");
  const double yaw0 = c.config.initial_state ? eulerFromQuat(c.config.initial_state->q_nb).z() : 0.0;
  const Geodetic pos0 = c.config.initial_state ? c.config.initial_state->pos : c.gnss.front().pos;
  const ImuSeries err = staticErrorIncrements(tested.imu, spans, pos0, yaw0);
  const BasicErrorSignal basic(err);
  const double t_first = tested.imu.front().t_s - tested.imu.front().dt_s;
  std::string md = fmt::format("Standstill spans of the tested IMU (static detector: gyro <= {:.3f} rad/s, accel <= {:.2f} m/s^2 std over 1 s, >= {:.1f} s, 0.5 s trimmed): ",
                               det.gyro_threshold_rad_s, det.accel_threshold_m_s2, a.min_static_s);
  for (const auto& sp : spans)
    md += fmt::format("{:.1f}-{:.1f} s, ", sp.t_begin_s - t_first, sp.t_end_s - t_first);
  md += fmt::format("({} detected spans dropped: median GNSS speed above {:.2f} m/s inside), ", moving_spans, a.max_static_speed_m_s);
  const Eigen::Vector3d bg = basic.meanGyro_rad_s() * kR2D, ba = basic.meanAccel_m_s2();
  md += fmt::format("total {:.1f} s.\nBasic biases (mean of the error signal): gyro [{:.3f} {:.3f} {:.3f}] deg/s, "
                    "accel [{:.3f} {:.3f} {:.3f}] m/s^2 (horizontal accel bias absorbed by levelling).\n\n",
                    basic.recordLength_s(), bg.x(), bg.y(), bg.z(), ba.x(), ba.y(), ba.z());
  fmt::print(stderr, "{}", md);
  GraftOptions go;
  go.seed = a.seed;
  ImuSelection sg = ref;
  sg.imu = graftBasic(ref.imu, basic, go);
  sg.profile = tested.profile;
  sg.label = "SG#1 (ref + tested standstill errors)";

  struct Item { std::string label; const ImuSelection* imu; };
  const std::vector<Item> items = {{"REF (reference IMU)", &ref}, {"SG#1 (grafted)", &sg}, {"REAL (tested IMU)", &tested}};
  std::vector<Evaluation> evs;
  std::vector<std::string> labels;
  std::vector<TimeWindow> outages;
  for (const auto& it : items) {
    fmt::print(stderr, "navigating {} ({}, outages)\n", it.label, a.estimator);
    const EstimationProblem p = problemReal(c, *it.imu, rc, true, true);
    const NavSolution s = runEstimator(a.estimator, p, rc);
    const std::string tag = it.label.substr(0, it.label.find(' '));
    writeNav((fs::path(a.out) / ("solution_" + tag + ".nav")).string(), s.states);
    evs.push_back(evaluateSolution(s, sol_ref.states, p.outages, rc.evaluation.options));
    labels.push_back(it.label);
    outages = p.outages;
    fmt::print(stderr, "  GNSS used {}, gated {}, withheld {}\n", s.gnss_used, s.gnss_rejected, s.gnss_withheld);
  }
  {
    std::string o = "start_s,end_s,data_start_s\n";
    for (const auto& w : outages) o += fmt::format("{:.3f},{:.3f},{:.3f}\n", w.start_s, w.end_s, t_first);
    writeFileAtomically((fs::path(a.out) / "outages.csv").string(), o);
  }
  md += fmt::format("ERR against SOL_REF (reference IMU, RTS, all GNSS), {} outages, {} estimator:\n\n", outages.size(), a.estimator);
  md += "| solution | outage RMS h (m) | RMS of per-outage max h (m) | RMS of max v (m) | RMS of max roll (deg) | RMS of max pitch (deg) | RMS of max heading (deg) |\n|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < evs.size(); ++i) {
    const auto& e = evs[i];
    md += fmt::format("| ERR {} | {:.2f} | {:.2f} | {:.2f} | {:.3f} | {:.3f} | {:.3f} |\n", labels[i],
                      e.outage_rms.horizontal_m, e.outage_max_rms.horizontal_m, e.outage_max_rms.vertical_m,
                      e.outage_max_rms.roll_rad * kR2D, e.outage_max_rms.pitch_rad * kR2D,
                      e.outage_max_rms.heading_rad * kR2D);
  }
  const auto& S = evs[1];
  const auto& R = evs[2];
  md += fmt::format("| DIFF = SG#1 - REAL | {:+.2f} | {:+.2f} | {:+.2f} | {:+.3f} | {:+.3f} | {:+.3f} |\n\n",
                    S.outage_rms.horizontal_m - R.outage_rms.horizontal_m,
                    S.outage_max_rms.horizontal_m - R.outage_max_rms.horizontal_m,
                    S.outage_max_rms.vertical_m - R.outage_max_rms.vertical_m,
                    (S.outage_max_rms.roll_rad - R.outage_max_rms.roll_rad) * kR2D,
                    (S.outage_max_rms.pitch_rad - R.outage_max_rms.pitch_rad) * kR2D,
                    (S.outage_max_rms.heading_rad - R.outage_max_rms.heading_rad) * kR2D);
  md += "Per outage: maximum horizontal error (m)\n\n| outage (s after start) |";
  for (const auto& l : labels) md += " " + l + " |";
  md += "\n|---|---|---|---|\n";
  for (std::size_t w = 0; w < evs[0].outages.size(); ++w) {
    const auto& win = evs[0].outages[w].window;
    md += fmt::format("| {:.0f}-{:.0f} |", win.start_s - t_first, win.end_s - t_first);
    for (const auto& e : evs) md += w < e.outages.size() ? fmt::format(" {:.2f} |", e.outages[w].max.horizontal_m) : " - |";
    md += "\n";
  }
  writeFileAtomically((fs::path(a.out) / "summary.md").string(), md);
  fmt::print("{}", md);
  fmt::print("wrote {}/summary.md, sol_ref.nav, solution_*.nav\n", a.out);
}

}  // namespace

void registerReal(CLI::App& app) {
  auto a = std::make_shared<RealArgs>();
  CLI::App* cmd = app.add_subcommand(
      "real", "real recording: estimators, errors at withheld GNSS check points and vs the reference, GNSS latency");
  cmd->add_option("case_dir", a->case_dir, "case directory")->required();
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--run-config", a->config, "run config YAML (outages:, gnss:, ekf:, fgo:); required")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &a->config);
  cmd->add_option("--imu", a->imu, "ref | tested | FILE (default ref)");
  cmd->add_option("--profile", a->profile, "IMU profile YAML")->check(CLI::ExistingFile);
  cmd->add_option("--estimator", a->estimators, "comma list of estimators (default ekf,rts,fgo)")->delimiter(',');
  addDeprecatedOption(cmd, "--estimators", "--estimator", &a->estimators);
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/real_plots.py");
  cmd->add_flag("--latency-scan", a->latency_scan, "estimate the GNSS time-tag latency per fix type");
  cmd->add_option("--latency-grid", a->latency_grid, "latencies (s) applied to --latency-types, outage errors for each")->delimiter(',');
  cmd->add_option("--latency-types", a->latency_types, "fix types the latency grid applies to (default 4,5)")->delimiter(',');
  cmd->add_option("--latency-estimators", a->latency_estimators, "estimators of the latency grid (default ekf,rts)")->delimiter(',');
  cmd->callback([a]() {
    requireValue(a->config, "--run-config");
    runReal(*a);
  });

  auto s = std::make_shared<RealSgArgs>();
  CLI::App* sg = app.add_subcommand(
      "real-sg", "real-data signal grafting: tested IMU errors from its own standstill spans onto the reference IMU");
  sg->add_option("case_dir", s->case_dir, "case directory (ref_imu.txt and tested_imu.txt)")->required();
  sg->add_option("--out", s->out, "output directory")->required();
  sg->add_option("--run-config", s->config, "run config YAML (outages:, gnss:, ekf:); required")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(sg, "--config", "--run-config", &s->config);
  sg->add_flag("--no-plots", s->no_plots, "accepted for a uniform vocabulary (real-sg writes no plots)");
  sg->add_option("--ref-profile", s->ref_profile, "reference IMU profile")->required()->check(CLI::ExistingFile);
  sg->add_option("--tested-profile", s->tested_profile, "tested IMU profile")->required()->check(CLI::ExistingFile);
  sg->add_option("--estimator", s->estimator, "estimator (default rts)");
  sg->add_option("--seed", s->seed, "grafting start offset seed (default 1)");
  sg->add_option("--static-gyro-threshold", s->detector_gyro_rad_s, "static detector gyro threshold (rad/s)");
  sg->add_option("--static-accel-threshold", s->detector_accel_m_s2, "static detector accel threshold (m/s^2)");
  sg->add_option("--min-static", s->min_static_s, "minimum standstill span (s)");
  sg->add_option("--max-static-speed", s->max_static_speed_m_s, "median GNSS speed (1-s chords) above which a detected span is not a standstill (m/s)");
  sg->callback([s]() {
    requireValue(s->config, "--run-config");
    runRealSg(*s);
  });
}

}  // namespace graftnav::app
