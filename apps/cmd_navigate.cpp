// graftnav navigate CASE_DIR --out OUT_DIR [--imu ref|tested|FILE] [--profile FILE]
//   [--estimator ekf|rts|...] [--outage-length S --outage-period S --outage-start S]
//   [--config FILE] [--free-inertial] [--decimate N] [--lenient] [--no-plots]
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "estimators.h"
#include "graftnav/core/case_config.h"
#include "graftnav/core/evaluation.h"
#include "graftnav/core/gnss_io.h"
#include "graftnav/core/imu_io.h"
#include "graftnav/core/imu_profile_io.h"
#include "graftnav/core/nav_interp.h"
#include "graftnav/core/nav_io.h"
#include "graftnav/core/rotation.h"
#include "graftnav/filters/alignment.h"
#include "report_io.h"
#include "run_config.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

struct NavigateArgs {
  std::string case_dir, out, imu = "ref", profile, estimator = "ekf", config;
  double outage_length = -1, outage_period = -1, outage_start = -1;
  bool free_inertial = false, lenient = false, no_plots = false;
  int decimate = 1;
};

std::string plotScriptPath() {
  if (const char* env = std::getenv("GRAFTNAV_PLOT_SCRIPT")) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const std::vector<fs::path> candidates = {
      exe.parent_path() / ".." / "scripts" / "plot_errors.py",
      exe.parent_path() / ".." / ".." / "scripts" / "plot_errors.py",
      fs::path("scripts") / "plot_errors.py"};
  for (const auto& c : candidates) {
    if (fs::exists(c)) return fs::weakly_canonical(c).string();
  }
  return candidates.front().string();
}

void runNavigate(const NavigateArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&]() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  if (!fs::is_directory(a.case_dir)) {
    throw std::runtime_error("case directory '" + a.case_dir + "' does not exist");
  }
  const CasePaths paths(a.case_dir);
  if (!CasePaths::exists(paths.caseYaml())) {
    throw std::runtime_error("'" + a.case_dir + "' is not a case directory: no case.yaml");
  }
  std::vector<std::string> warnings, notes;
  const CaseConfig cfg = loadCaseConfig(paths.caseYaml(), &warnings);
  RunConfig rc;
  if (!a.config.empty()) rc = loadRunConfig(a.config, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  rc.ekf.output_decimation = a.decimate;

  // IMU and its profile.
  std::string imu_path, imu_label;
  double rate_hz = cfg.imu_rate_hz;
  std::optional<ImuProfile> profile;
  bool noise_given = false;
  if (a.imu == "ref") {
    imu_path = paths.refImu();
    profile = cfg.reference_imu;
    noise_given = cfg.reference_imu_noise_given;
  } else if (a.imu == "tested") {
    imu_path = paths.testedImu();
    profile = cfg.tested_imu;
    noise_given = cfg.tested_imu_noise_given;
    rate_hz = cfg.testedImuRateHz();
  } else {
    imu_path = a.imu;  // e.g. a grafted IMU: navigated with the tested IMU's profile by default
    profile = cfg.tested_imu;
    noise_given = cfg.tested_imu_noise_given;
    rate_hz = cfg.testedImuRateHz();
  }
  if (!a.profile.empty()) {
    std::vector<std::string> pw;
    profile = loadImuProfile(a.profile, &pw);
    for (const auto& w : pw) fmt::print(stderr, "warning: {}\n", w);
    noise_given = true;
  }
  if (!CasePaths::exists(imu_path)) throw std::runtime_error("IMU file '" + imu_path + "' not found");
  const bool needs_profile = !a.free_inertial;
  if (needs_profile && (!profile || !noise_given)) {
    throw std::runtime_error("no noise parameters for IMU '" + a.imu +
                             "' in case.yaml: pass --profile FILE (configs/imu/*.yaml)");
  }
  imu_label = profile && !profile->name.empty() ? profile->name : a.imu;

  ImuReadOptions ro;
  ro.nominal_rate_hz = rate_hz;
  if (a.lenient) ro.policy = ImuReadPolicy::real();
  fmt::print(stderr, "[{:6.1f} s] reading {}\n", elapsed(), imu_path);
  EstimationProblem pr;
  pr.imu = readImu(imu_path, ro);
  if (profile) pr.imu_profile = *profile;
  if (pr.imu.empty()) throw std::runtime_error("IMU file '" + imu_path + "' holds no sample");
  if (!a.free_inertial) {
    if (!CasePaths::exists(paths.gnssPos())) {
      throw std::runtime_error("GNSS file '" + paths.gnssPos() + "' not found");
    }
    const std::string ft = CasePaths::exists(paths.gnssFixType()) ? paths.gnssFixType() : "";
    pr.gnss = readGnss(paths.gnssPos(), ft, a.lenient ? GnssReadPolicy::real() : GnssReadPolicy{});
  }
  if (cfg.lever_arm_m) {
    pr.lever_arm_b_m = *cfg.lever_arm_m;
  } else if (!a.free_inertial) {
    fmt::print(stderr, "warning: case.yaml has no lever_arm_m: using a zero lever arm\n");
  }

  // Reference for the evaluation: truth.nav, else the case's reference solution.
  NavSeries reference;
  std::string reference_name;
  if (CasePaths::exists(paths.truthNav())) {
    reference = readNav(paths.truthNav());
    reference_name = paths.truthNav();
  } else if (auto ref = paths.referenceSolution(cfg); ref && CasePaths::exists(*ref)) {
    reference = readNav(*ref, a.lenient ? NavReadPolicy::real() : NavReadPolicy{});
    reference_name = *ref;
  }

  // Initial state: truth (interpolated to the start of the first IMU interval) when present,
  // else case.yaml initial_state; data-driven alignment when the config asks for it.
  const double t_first = pr.imu.front().t_s - pr.imu.front().dt_s;
  const int week = cfg.gnss_week.value_or(reference.empty() ? 0 : reference.front().gnss_week);
  if (!reference.empty() && CasePaths::exists(paths.truthNav()) &&
      interpolateNav(reference, std::max(t_first, reference.front().t_s), 1e-3)) {
    pr.initial = *interpolateNav(reference, std::max(t_first, reference.front().t_s), 1e-3);
    notes.push_back("initial state from truth.nav at t=" + fmt::format("{:.3f}", pr.initial.t_s));
  } else if (cfg.initial_state) {
    pr.initial = *cfg.initial_state;
    notes.push_back("initial state from case.yaml initial_state");
  } else if (rc.alignment.mode == "given" || a.free_inertial) {
    throw std::runtime_error("no initial state: the case has neither field/truth.nav nor "
                             "case.yaml initial_state (set ekf.alignment: static|motion)");
  }
  pr.initial.gnss_week = week;
  if (!a.free_inertial && rc.alignment.mode == "static") {
    if (!cfg.initial_state && reference.empty() && pr.gnss.empty()) {
      throw std::runtime_error("static alignment needs a position (initial_state or GNSS)");
    }
    Geodetic pos = pr.initial.pos;
    if (!cfg.initial_state && reference.empty()) pos = pr.gnss.front().pos;
    const StaticAlignment al =
        alignStatic(pr.imu, t_first, rc.alignment.static_duration_s, pos, pr.imu_profile);
    NavState s;
    s.t_s = t_first + rc.alignment.static_duration_s;
    s.pos = pos;
    s.gnss_week = week;
    Eigen::Vector3d e = al.euler_rad;
    if (!al.heading_valid) {
      fmt::print(stderr, "warning: {}\n", al.note);
      notes.push_back(al.note);
      if (cfg.initial_state) {
        e.z() = eulerFromQuat(cfg.initial_state->q_nb).z();
        notes.push_back("heading taken from case.yaml initial_state");
      } else {
        throw std::runtime_error(al.note + "; use ekf.alignment: motion");
      }
    }
    s.q_nb = quatFromEuler(e);
    pr.initial = s;
    pr.initial_sigma << 1.0, 1.0, 1.0, 0.05, 0.05, 0.05, std::max(al.level_std_rad, 1e-4),
        std::max(al.level_std_rad, 1e-4), al.heading_valid ? std::max(al.heading_std_rad, 1e-3) : 0.05;
    notes.push_back(fmt::format("static alignment: roll {:.4f} pitch {:.4f} yaw {:.4f} deg",
                                e.x() * kRadToDeg, e.y() * kRadToDeg, e.z() * kRadToDeg));
  } else if (!a.free_inertial && rc.alignment.mode == "motion") {
    const auto st = alignInMotion(pr.imu, pr.gnss, pr.lever_arm_b_m, rc.alignment.motion);
    if (!st) throw std::runtime_error("in-motion alignment: no GNSS epoch reaches the minimum speed");
    pr.initial = *st;
    pr.initial.gnss_week = week;
    pr.initial_sigma << 0.5, 0.5, 0.5, 0.3, 0.3, 0.3, 1.0 * kDegToRad, 1.0 * kDegToRad,
        3.0 * kDegToRad;
    notes.push_back(fmt::format("in-motion alignment at t={:.3f}", st->t_s));
  }

  // Outages: config section, overridden by the command line.
  const bool cli_outage = a.outage_length >= 0 || a.outage_period >= 0 || a.outage_start >= 0;
  OutageScheduleConfig oc = rc.outages;
  if (a.outage_length >= 0) oc.length_s = a.outage_length;
  if (a.outage_period >= 0) oc.period_s = a.outage_period;
  if (a.outage_start >= 0) oc.start_s = a.outage_start;
  if ((rc.outages_given || cli_outage) && !a.free_inertial) {
    pr.outages = buildOutageWindows(oc, t_first, pr.imu.back().t_s);
  }

  const std::string estimator = a.free_inertial ? "free-inertial" : a.estimator;
  fmt::print(stderr, "[{:6.1f} s] {} on {} IMU samples, {} GNSS fixes, {} outages\n", elapsed(),
             estimator, pr.imu.size(), pr.gnss.size(), pr.outages.size());
  int last_decile = -1;
  const ProgressFn progress = [&](double f) {
    const int d = static_cast<int>(f * 10.0);
    if (d != last_decile) {
      last_decile = d;
      fmt::print(stderr, "[{:6.1f} s] {} {:3d} %\n", elapsed(), estimator, d * 10);
    }
  };
  const double t_run0 = elapsed();
  const NavSolution sol = runEstimator(estimator, pr, rc, progress);
  const double run_time = elapsed() - t_run0;

  fs::create_directories(a.out);
  const std::string nav_out = (fs::path(a.out) / "solution.nav").string();
  writeNav(nav_out, sol.states);
  fmt::print("{}: {} epochs -> {} ({:.2f} s)\n", estimator, sol.states.size(), nav_out, run_time);
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
    const std::string w = runPlotScript(plotScriptPath(), a.out);
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
