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
#include "graftnav/io/imu_recording.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "graftnav/mismatch/diagnosis_setup.h"
#include "graftnav/mismatch/diagnose_config.h"
#include "graftnav/mismatch/diagnosis_case.h"
#include "graftnav/mismatch/navigation_level.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {
namespace {

// The flags; --options is configs/diagnose.yaml -> DiagnoseOptions (unknown keys are warnings).
struct DiagnoseArgs {
  std::string case_dir, out, estimator, options, run_config, tested_profile;
  OutageOverrides outage;
  bool no_plots = false;
};

// outages.csv and the DIFF lines of the navigation level.
void writeNavigationOutputs(const std::string& out, const NavigationComparison& nav) {
  writeNavigationOutagesCsv(out, nav);
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

// IMU_SG3.txt, held or written as its recording's pass comes.
void writeSg3(const std::string& path, const DiagnosisResult& res) {
  if (!res.sg3_recording) return writeImu(path, res.sg3);
  ImuWriter writer(path);
  res.sg3_recording->pass([&writer](const ImuSeries& block) {
    for (const ImuSample& s : block) writer.add(s);
  });
  writer.commit();
}

// The whole command: load, diagnose, optionally navigate, write and print.
void runDiagnose(const DiagnoseArgs& args) {
  // The run config, read once before any output: its grafting section for SG#2, the rest for the
  // navigation level.
  RunConfig rc;
  std::vector<std::string> notes;
  if (!args.run_config.empty()) rc = loadRunConfig(args.run_config, &notes);
  requireTimeRangeUnset(rc.time_range, args.run_config, "graftnav diagnose");
  std::filesystem::create_directories(args.out);
  // One load of the case for both levels: GNSS only when the navigation level runs.
  CaseLoadOptions lo;
  lo.lenient = true;
  lo.load_gnss = !args.estimator.empty() && CasePaths::exists(CasePaths(args.case_dir).gnssPos());
  lo.load_reference = false;  // diagnosisInputsOf reads it after the simulation
  CaseInputs c = loadCaseInputs(args.case_dir, lo);
  std::vector<std::string> warnings = c.warnings;
  DiagnoseOptions opt;
  if (!args.options.empty()) opt = loadDiagnoseConfig(args.options, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  if (!CasePaths::exists(c.paths().testedImu()))
    throw std::runtime_error(c.paths().testedImu() +
                             ": diagnose needs the tested IMU's field recording");
  ImuSelection ref_imu = selectImu(c, "ref", "", true);
  ImuSelection tested = selectImu(c, "tested", "", true, false);  // the finder reads its file
  for (const ImuSelection* sel : {&ref_imu, &tested})
    if (!sel->read_summary.empty()) fmt::print(stderr, "warning: {}\n", sel->read_summary);
  const DiagnosisCaseOptions co{args.tested_profile, !args.estimator.empty()};
  DiagnosisInputs in =
      diagnosisInputsOf(c, rc, &ref_imu, &tested, co, &notes,
                        [](const std::string& l) { fmt::print(stderr, "{}\n", l); });
  fmt::print(stderr, "diagnose: {} reference, {} tested samples; simulation: {}\n",
             in.reference.size(), in.real_recording ? in.real_recording->samples : in.real.size(),
             in.simulation_kind);
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
      const ImuSeries sg3 = res.sg3_recording ? collectRecording(*res.sg3_recording) : res.sg3;
      nav = compareNavigation(c, tested, args.estimator, rc, args.outage, sg2, sg3,
                              estimatorTable(), &res.notes);
    } catch (const std::exception& e) {
      res.notes.push_back(std::string("navigation level skipped: ") + e.what());
      fmt::print(stderr, "warning: navigation level skipped: {}\n", e.what());
    }
  }
  writeDiagnosisFiles(args.out, res, nav ? &*nav : nullptr);
  if (nav) writeNavigationOutputs(args.out, *nav);
  writeSg3(args.out + "/IMU_SG3.txt", res);
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
  cmd->add_option("--options", args->options, "diagnose options file (see configs/diagnose.yaml)");
  addDeprecatedOption(cmd, "--config", "--options", &args->options);
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
