// graftnav diagnose CASE_DIR --out OUT_DIR [--estimator ekf|rts|fgo] [--config FILE] [--no-plots]
// The mismatch finder: where the simulation of the tested IMU and its real recording
// differ, which physics explains it, and how much the fit improves when that physics is grafted.
#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <optional>
#include <memory>
#include <string>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/problem.h"
#include "cli_vocabulary.h"
#include "commands.h"
#include "script_locator.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/sg/sg_statistics.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/reference_solution.h"
#include "graftnav/case/run_config.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/io/case_config.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "graftnav/mismatch/diagnosis_setup.h"
#include "graftnav/mismatch/diagnose_config.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {
namespace {

// configs/diagnose.yaml -> DiagnoseOptions (every key optional; unknown keys are warnings).
// Navigation level: SG#2, SG#3 and REAL navigated with one estimator and outage schedule,
// evaluated against SOL_REF (truth, the case's reference solution, or the RTS-smoothed reference
// IMU). Throws std::runtime_error when the case cannot be navigated.
NavigationComparison navigateComparison(const CaseInputs& c, const ImuSelection& tested,
                                        const std::string& estimator, const RunConfig& rc,
                                        const OutageOverrides& outages, const ImuSeries& sg2,
                                        const ImuSeries& sg3, std::vector<std::string>* notes) {
  if (c.gnss.empty()) throw std::runtime_error(c.paths().gnssPos() + " not found or empty");
  const OutageScheduleConfig oc = outages.appliedTo(rc.outages);
  const NavSeries sol_ref =
      resolveReferenceSolution(
          c, [&c] { return selectImu(c, "ref", "", true); }, rc, estimatorTable())
          .states;
  if (c.reference.empty()) notes->push_back("SOL_REF: RTS-smoothed reference IMU with all GNSS");
  if (!tested.profile_given)
    notes->push_back(
        "tested_imu has no noise parameters in case.yaml: the estimator's defaults are used");
  NavigationComparison nav;
  nav.estimator = estimator;
  std::array<Evaluation, 3> ev;
  const std::array<const ImuSeries*, 3> series = {&sg2, &sg3, &tested.imu};
  for (int k = 0; k < 3; ++k) {
    ImuSelection s = tested;
    s.imu = *series[k];
    std::vector<std::string> n;
    const EstimationProblem p = makeProblem(c, s, rc, oc, &n);
    const NavSolution sol = estimatorTable().run(estimator, p, rc);
    ev[k] = evaluateSolution(sol, sol_ref, p.outages, rc.evaluation.options);
    if (k == 2) {
      nav.outage_count = static_cast<int>(p.outages.size());
      nav.outage_length_s = p.outages.empty() ? 0.0 : p.outages.front().length_s();
      for (const auto& m : n) notes->push_back(m);
    }
  }
  nav.err_sg2 = ev[0].outage_rms;
  nav.err_sg3 = ev[1].outage_rms;
  nav.err_real = ev[2].outage_rms;
  nav.diff_before = relativeDifference(nav.err_sg2, nav.err_real);
  nav.diff_after = relativeDifference(nav.err_sg3, nav.err_real);
  // Which outages carry |ERR_SG2 - ERR_REAL| (per-outage maximum horizontal drift).
  double total = 0.0;
  for (std::size_t i = 0; i < ev[2].outages.size(); ++i) {
    NavigationComparison::OutageShare o;
    o.window = ev[2].outages[i].window;
    o.real_horizontal_m = ev[2].outages[i].max.horizontal_m;
    for (const auto& od : ev[0].outages)
      if (std::abs(od.window.start_s - o.window.start_s) < 1e-6)
        o.sg2_horizontal_m = od.max.horizontal_m;
    for (const auto& od : ev[1].outages)
      if (std::abs(od.window.start_s - o.window.start_s) < 1e-6)
        o.sg3_horizontal_m = od.max.horizontal_m;
    o.share = std::abs(o.sg2_horizontal_m - o.real_horizontal_m);
    total += o.share;
    nav.outages.push_back(o);
  }
  for (auto& o : nav.outages) o.share = total > 0.0 ? o.share / total : 0.0;
  return nav;
}

struct DiagnoseArgs {
  std::string case_dir, out, estimator, config, run_config, tested_profile;
  OutageOverrides outage;
  bool no_plots = false;
};

// The finder's inputs from the loaded case: records, plausible ranges, and the simulation with
// its priors (SG#2 from the lab data, or the static-bias simulation without). The records are
// moved out of the selections, so the case holds each IMU series once. The truth (the attitude
// along the record) is handed over when the finder needs it: read from its file, or copied from
// the case when the navigation level holds it.
DiagnosisInputs diagnosisInputsOf(CaseInputs& c, const DiagnoseArgs& args, const RunConfig& rc,
                                  ImuSelection* ref_imu, ImuSelection* tested,
                                  std::vector<std::string>* notes) {
  const CaseConfig& cfg = c.config;
  DiagnosisInputs in;
  in.case_name = cfg.name;
  in.reference = std::move(ref_imu->imu);
  in.real = std::move(tested->imu);
  in.initial_state = cfg.initial_state;
  // The ranges a claimed value must lie in: the tested profile's (its class, or its grade's).
  if (!args.tested_profile.empty()) {
    std::vector<std::string> profile_warnings;
    in.tested_plausible_ranges =
        loadImuProfile(args.tested_profile, &profile_warnings).plausible_ranges;
    for (const auto& w : profile_warnings) fmt::print(stderr, "warning: {}\n", w);
  } else if (cfg.tested_imu) {
    in.tested_plausible_ranges = cfg.tested_imu->plausible_ranges;
  }
  if (in.tested_plausible_ranges) in.tested_plausible_ranges->validate();
  if (CasePaths::exists(c.paths().labStatic())) {
    fmt::print(stderr, "diagnose: lab data found: simulation = SG#2 from the lab calibration\n");
    PerSensor<double> ref_scale_std;
    if (cfg.reference_imu) {
      ref_scale_std[Sensor::gyro] = cfg.reference_imu->gyro_scale_std;
      ref_scale_std[Sensor::accel] = cfg.reference_imu->accel_scale_std;
    }
    const std::string case_dir = args.case_dir;
    LabData lab = loadLabData(case_dir);
    if (lab.has_static) checkLabStaticRecord(lab.staticRecordSeconds(), lab.static_file, 0.0);
    simulateFromLab(lab, rc.grafting.start_offset_s, ref_scale_std, &in,
                    [case_dir] { return loadLabData(case_dir); });
  } else {
    std::vector<std::string> warnings;
    simulateWithoutLab(&in, notes, &warnings);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  }
  // A case with a truth trajectory is simulated: its reference IMU may lack navigation physics.
  // The truth is as long as the records: the finder reads it when it needs the attitude, after
  // it has binned them; the navigation level reads it here (its SOL_REF), after the simulation.
  const std::string truth = c.paths().truthNav();
  in.reference_is_simulated = CasePaths::exists(truth);
  if (args.estimator.empty()) {
    if (in.reference_is_simulated) in.read_attitude = [truth] { return readNav(truth); };
    return in;
  }
  const std::size_t warned = c.warnings.size();
  loadCaseReference(&c, true);
  for (std::size_t k = warned; k < c.warnings.size(); ++k)
    fmt::print(stderr, "warning: {}\n", c.warnings[k]);
  // The case holds it for the navigation level anyway: the finder takes a copy only while it
  // builds the regressors.
  if (in.reference_is_simulated) in.read_attitude = [&c] { return c.reference; };
  return in;
}

// outages.csv and the DIFF lines of the navigation level.
void writeNavigationOutputs(const std::string& out, const NavigationComparison& nav) {
  std::string csv = "t_start,t_end,sg2_horizontal_m,sg3_horizontal_m,real_horizontal_m,share\n";
  for (const auto& o : nav.outages)
    csv +=
        fmt::format("{:.3f},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f}\n", o.window.start_s, o.window.end_s,
                    o.sg2_horizontal_m, o.sg3_horizontal_m, o.real_horizontal_m, o.share);
  writeFileAtomically(out + "/outages.csv", csv);
  const auto pct = [](const DriftStats& d) {
    return fmt::format("{:.1f} / {:.1f} / {:.1f} / {:.1f} / {:.1f} %", 100 * d.horizontal_m,
                       100 * d.vertical_m, 100 * d.roll_rad, 100 * d.pitch_rad,
                       100 * d.heading_rad);
  };
  fmt::print("  DIFF before (SG2) h/v/roll/pitch/heading: {}\n", pct(nav.diff_before));
  fmt::print("  DIFF after  (SG3) h/v/roll/pitch/heading: {}\n", pct(nav.diff_after));
}

// The effects and residual RMS on stdout.
void printSummary(const std::string& case_name, const DiagnosisResult& res) {
  fmt::print("diagnosis of {}: {} located spans, {} effects, {} unexplained spans\n", case_name,
             res.located.size(), res.effects.size(), res.unexplained.size());
  for (const Effect& e : res.effects) {
    std::string p;
    for (const EffectParameter& q : e.parameters) {
      if (!q.text.empty()) {
        p += q.key + "=" + q.text + " ";
        continue;
      }
      p += q.key + "=[";
      for (std::size_t i = 0; i < q.values.size(); ++i)
        p += fmt::format("{}{:.4g}+-{:.2g}", i ? " " : "", q.values[i], q.sigma[i]);
      p += "] ";
    }
    fmt::print("  {} ({}): {}delta_bic {:.1f} cv_gain {:.4f}\n", e.name(), scopeName(e.sensor), p,
               e.delta_bic, e.cv_gain);
  }
  const auto line = [](const char* name, const ChannelRms& r) {
    fmt::print("  {:<28} gyro [{:.4f} {:.4f} {:.4f}] deg/s  accel [{:.4f} {:.4f} {:.4f}] m/s^2\n",
               name, r.gyro.x() * units::kRadToDeg, r.gyro.y() * units::kRadToDeg,
               r.gyro.z() * units::kRadToDeg, r.accel.x(), r.accel.y(), r.accel.z());
  };
  line("residual RMS before", res.rms_before);
  line("residual RMS after", res.rms_after);
  if (res.has_holdout) {
    line("2nd half before (1st-half fit)", res.holdout_before);
    line("2nd half after (1st-half fit)", res.holdout_after);
  }
}

// The whole command: load, diagnose, optionally navigate, write and print.
void runDiagnose(const DiagnoseArgs& args) {
  std::filesystem::create_directories(args.out);
  // One load of the case for both levels: GNSS only when the navigation level runs.
  CaseLoadOptions lo;
  lo.lenient = true;
  lo.load_gnss = !args.estimator.empty() && CasePaths::exists(CasePaths(args.case_dir).gnssPos());
  lo.load_reference = false;  // diagnosisInputsOf reads it after the simulation
  CaseInputs c = loadCaseInputs(args.case_dir, lo);
  std::vector<std::string> warnings = c.warnings;
  DiagnoseOptions opt;
  if (!args.config.empty()) opt = loadDiagnoseConfig(args.config, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  // The run config, read once: its grafting section for SG#2, the rest for the navigation level.
  RunConfig rc;
  std::vector<std::string> notes;
  if (!args.run_config.empty()) rc = loadRunConfig(args.run_config, &notes);
  if (!CasePaths::exists(c.paths().testedImu()))
    throw std::runtime_error(c.paths().testedImu() +
                             ": diagnose needs the tested IMU's field recording");
  ImuSelection ref_imu = selectImu(c, "ref", "", true);
  ImuSelection tested = selectImu(c, "tested", "", true);
  for (const ImuSelection* sel : {&ref_imu, &tested})
    if (!sel->read_summary.empty()) fmt::print(stderr, "warning: {}\n", sel->read_summary);
  DiagnosisInputs in = diagnosisInputsOf(c, args, rc, &ref_imu, &tested, &notes);
  fmt::print(stderr, "diagnose: {} reference, {} tested samples; simulation: {}\n",
             in.reference.size(), in.real.size(), in.simulation_kind);
  const auto remake_simulated = in.remake_simulated;
  // The finder releases each record once binned; the navigation level reads them again.
  DiagnosisResult res = diagnose(std::move(in), opt);
  res.notes.insert(res.notes.end(), notes.begin(), notes.end());
  std::optional<NavigationComparison> nav;
  if (!args.estimator.empty()) {
    try {
      fmt::print(stderr, "diagnose: navigating SG#2, SG#3 and REAL with {}\n", args.estimator);
      tested = selectImu(c, "tested", "", true);  // REAL, navigated as the tested IMU
      const ImuSeries sg2 = remake_simulated(selectImu(c, "ref", "", true).imu);
      nav =
          navigateComparison(c, tested, args.estimator, rc, args.outage, sg2, res.sg3, &res.notes);
    } catch (const std::exception& e) {
      res.notes.push_back(std::string("navigation level skipped: ") + e.what());
      fmt::print(stderr, "warning: navigation level skipped: {}\n", e.what());
    }
  }
  writeDiagnosisFiles(args.out, res, nav ? &*nav : nullptr);
  if (nav) writeNavigationOutputs(args.out, *nav);
  writeImu(args.out + "/IMU_SG3.txt", res.sg3);
  printSummary(c.config.name, res);
  fmt::print("  wrote {0}/diagnosis.json, {0}/diagnosis.md, {0}/residual.csv, {0}/IMU_SG3.txt\n",
             args.out);
  if (!args.no_plots) {
    const std::string w = runPythonScript("plot_diagnosis.py", {args.out});
    if (!w.empty()) fmt::print(stderr, "warning: {}; the numbers are written\n", w);
  }
}

}  // namespace

void registerDiagnose(CLI::App& app) {
  auto args = std::make_shared<DiagnoseArgs>();
  CLI::App* cmd = app.add_subcommand(
      "diagnose",
      "Mismatch finder: locate, explain and model where the simulated and the real tested IMU differ");
  cmd->add_option("case_dir", args->case_dir, "case directory")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--estimator", args->estimator,
                  "also navigate SG#2, SG#3 and REAL with this estimator (ekf|rts|fgo)");
  cmd->add_option("--options", args->config, "diagnose options file (see configs/diagnose.yaml)");
  addDeprecatedOption(cmd, "--config", "--options", &args->config);
  cmd->add_flag("--no-plots", args->no_plots, "do not run scripts/runtime/plot_diagnosis.py");
  cmd->add_option("--run-config", args->run_config,
                  "run config of the estimator (configs/navigate.yaml: ekf:, outages:, ...)");
  cmd->add_option("--tested-profile", args->tested_profile,
                  "IMU profile of the tested IMU (configs/imu/*.yaml): its plausible_ranges "
                  "replace those of case.yaml's tested_imu (default: the grade's class)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--outage-length", args->outage.length_s, "outage length (s), with --estimator");
  cmd->add_option("--outage-period", args->outage.period_s, "outage start-to-start period (s)");
  cmd->add_option("--outage-start", args->outage.start_s,
                  "first outage start after the first epoch (s)");
  cmd->callback([args]() { runDiagnose(*args); });
}

}  // namespace graftnav::app
