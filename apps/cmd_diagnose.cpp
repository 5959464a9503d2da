// graftnav diagnose CASE_DIR --out OUT_DIR [--estimator ekf|rts|fgo] [--config FILE] [--no-plots]
// The mismatch finder (issue 7): where the simulation of the tested IMU and its real recording
// differ, which physics explains it, and how much the fit improves when that physics is grafted.
#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "graftnav/core/calibration/lab_calibration.h"
#include "graftnav/core/calibration/lab_data.h"
#include "graftnav/core/case_config.h"
#include "graftnav/core/graft_case.h"
#include "graftnav/core/imu_io.h"
#include "graftnav/core/nav_io.h"
#include "graftnav/core/mismatch/diagnosis.h"
#include "graftnav/core/mismatch/diagnosis_report.h"
#include "graftnav/core/units.h"

namespace graftnav::app {
namespace {

// configs/diagnose.yaml -> DiagnoseOptions (every key optional; unknown keys are warnings).
DiagnoseOptions loadDiagnoseConfig(const std::string& path, std::vector<std::string>* warnings) {
  DiagnoseOptions o;
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  auto num = [&](const YAML::Node& n, const std::string& key, double* out) {
    try {
      *out = n.as<double>();
    } catch (const YAML::Exception&) {
      throw std::runtime_error(fmt::format("{}:{}: key '{}' must be a number", path,
                                           n.Mark().line + 1, key));
    }
  };
  for (const auto& kv : root) {
    const std::string k = kv.first.as<std::string>();
    const YAML::Node& v = kv.second;
    double d = 0.0;
    if (k == "bin_s") num(v, k, &o.bin_s);
    else if (k == "margin_s") num(v, k, &o.margin_s);
    else if (k == "window_s") num(v, k, &o.locate.window_s);
    else if (k == "locate_false_alarm") num(v, k, &o.locate.false_alarm);
    else if (k == "knot_spacing_s") num(v, k, &o.library.knot_spacing_s);
    else if (k == "max_knots") { num(v, k, &d); o.library.max_knots = static_cast<int>(d); }
    else if (k == "min_delta_bic") num(v, k, &o.selection.min_delta_bic);
    else if (k == "min_cv_gain") num(v, k, &o.selection.min_cv_gain);
    else if (k == "folds") { num(v, k, &d); o.selection.folds = static_cast<int>(d); }
    else if (k == "max_terms") { num(v, k, &d); o.selection.max_terms = static_cast<int>(d); }
    else if (k == "max_time_offset_s") num(v, k, &o.time_offset.max_offset_s);
    else if (k == "holdout") o.holdout = v.as<bool>();
    else if (k == "detect_quantization") o.detect_quantization = v.as<bool>();
    else warnings->push_back(fmt::format("{}:{}: unknown key '{}' ignored", path, kv.first.Mark().line + 1, k));
  }
  o.validate();
  return o;
}

// scripts/plot_diagnosis.py next to the build tree (the binary lives in the build directory).
std::string findPlotScript() {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (fs::path p = exe.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path()) {
    const fs::path s = p / "scripts" / "plot_diagnosis.py";
    if (fs::exists(s)) return s.string();
  }
  return {};
}

}  // namespace

void registerDiagnose(CLI::App& app) {
  struct Args {
    std::string case_dir, out, estimator, config;
    bool no_plots = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "diagnose", "Mismatch finder: locate, explain and model where the simulated and the real tested IMU differ");
  cmd->add_option("case_dir", args->case_dir, "case directory")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--estimator", args->estimator,
                  "also navigate SG#2, SG#3 and REAL with this estimator (ekf|rts|fgo)");
  cmd->add_option("--config", args->config, "options file (see configs/diagnose.yaml)");
  cmd->add_flag("--no-plots", args->no_plots, "do not run scripts/plot_diagnosis.py");
  cmd->callback([args]() {
    std::filesystem::create_directories(args->out);
    const CasePaths paths(args->case_dir);
    std::vector<std::string> warnings;
    const CaseConfig cfg = loadCaseConfig(paths.caseYaml(), &warnings);
    DiagnoseOptions opt;
    if (!args->config.empty()) opt = loadDiagnoseConfig(args->config, &warnings);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    if (!args->estimator.empty())
      fmt::print(stderr, "warning: --estimator {}: the navigation level is not wired into diagnose "
                         "yet; only the signal level is reported (diff_before/diff_after null)\n",
                 args->estimator);

    ImuReadOptions ro;
    ro.policy = ImuReadPolicy::real();
    ro.nominal_rate_hz = cfg.imu_rate_hz;
    ReadReport ref_report, tested_report;
    const ImuSeries ref = readImu(paths.refImu(), ro, &ref_report);
    ro.nominal_rate_hz = cfg.testedImuRateHz();
    if (!CasePaths::exists(paths.testedImu()))
      throw std::runtime_error(paths.testedImu() + ": diagnose needs the tested IMU's field recording");
    const ImuSeries real = readImu(paths.testedImu(), ro, &tested_report);
    for (const ReadReport* r : {&ref_report, &tested_report})
      if (!r->clean()) fmt::print(stderr, "warning: {}\n", r->summary());

    DiagnosisInputs in;
    in.case_name = cfg.name;
    in.reference = ref;
    in.real = real;
    in.initial_state = cfg.initial_state;
    // A case with a truth trajectory is simulated: its reference IMU may lack navigation physics.
    in.reference_is_simulated = CasePaths::exists(paths.truthNav());
    if (in.reference_is_simulated) in.attitude = readNav(paths.truthNav());
    std::vector<std::string> notes;
    if (CasePaths::exists(paths.labStatic())) {
      fmt::print(stderr, "diagnose: lab data found: simulation = SG#2 from the lab calibration\n");
      const LabData lab = loadLabData(args->case_dir);
      const LabCalibrationReport report = calibrateLab(lab);
      const GraftedCase g = graftCase(ref, report);
      in.simulated = g.sg2;
      in.simulation_kind = "SG#2 (lab calibration + grafting)";
      in.lab_gyro_M_sigma = report.result.gyro.M_sigma;
      in.lab_accel_M_sigma = report.result.accel.M_sigma;
      if (report.result.gyro.has_allan)
        in.lab_gyro_bias_instability_rad_s = report.result.gyro.allan.bias_instability.maxCoeff();
      if (report.result.accel.has_allan)
        in.lab_accel_bias_instability_m_s2 = report.result.accel.allan.bias_instability.maxCoeff();
    } else {
      const StaticBiasSimulation sim = simulateFromReferenceAndStaticBias(ref, real);
      in.simulated = sim.simulated;
      in.simulation_kind = fmt::format(
          "reference IMU + tested IMU static bias (no lab data; bias from the static span {:.2f}-{:.2f} s: "
          "gyro [{:.4f} {:.4f} {:.4f}] deg/s, accel [{:.4f} {:.4f} {:.4f}] m/s^2)",
          sim.t_start_s, sim.t_end_s, sim.gyro_bias_rad_s.x() * units::kRadToDeg,
          sim.gyro_bias_rad_s.y() * units::kRadToDeg, sim.gyro_bias_rad_s.z() * units::kRadToDeg,
          sim.accel_bias_m_s2.x(), sim.accel_bias_m_s2.y(), sim.accel_bias_m_s2.z());
      notes.push_back("the reference IMU's own errors are in the simulation: effects are relative to it");
    }
    fmt::print(stderr, "diagnose: {} reference, {} tested samples; simulation: {}\n", ref.size(),
               real.size(), in.simulation_kind);
    DiagnosisResult res = diagnose(in, opt);
    res.notes.insert(res.notes.end(), notes.begin(), notes.end());
    writeDiagnosisFiles(args->out, res);
    writeImu(args->out + "/IMU_SG3.txt", res.sg3);

    fmt::print("diagnosis of {}: {} located spans, {} effects, {} unexplained spans\n", cfg.name,
               res.located.size(), res.effects.size(), res.unexplained.size());
    for (const Effect& e : res.effects) {
      std::string p;
      for (const EffectParameter& q : e.parameters) {
        if (!q.text.empty()) { p += q.key + "=" + q.text + " "; continue; }
        p += q.key + "=[";
        for (std::size_t i = 0; i < q.values.size(); ++i)
          p += fmt::format("{}{:.4g}+-{:.2g}", i ? " " : "", q.values[i], q.sigma[i]);
        p += "] ";
      }
      fmt::print("  {} ({}): {}delta_bic {:.1f} cv_gain {:.4f}\n", e.name, e.sensor, p, e.delta_bic, e.cv_gain);
    }
    auto line = [](const char* name, const ChannelRms& r) {
      fmt::print("  {:<28} gyro [{:.4f} {:.4f} {:.4f}] deg/s  accel [{:.4f} {:.4f} {:.4f}] m/s^2\n", name,
                 r.gyro.x() * units::kRadToDeg, r.gyro.y() * units::kRadToDeg, r.gyro.z() * units::kRadToDeg,
                 r.accel.x(), r.accel.y(), r.accel.z());
    };
    line("residual RMS before", res.rms_before);
    line("residual RMS after", res.rms_after);
    if (res.has_holdout) {
      line("2nd half before (1st-half fit)", res.holdout_before);
      line("2nd half after (1st-half fit)", res.holdout_after);
    }
    fmt::print("  wrote {0}/diagnosis.json, {0}/diagnosis.md, {0}/residual.csv, {0}/IMU_SG3.txt\n", args->out);
    if (!args->no_plots) {
      const std::string script = findPlotScript();
      if (script.empty()) {
        fmt::print(stderr, "warning: scripts/plot_diagnosis.py not found; no plots\n");
      } else {
        // matplotlib is installed for the system interpreter; GRAFTNAV_PYTHON overrides.
        const char* env = std::getenv("GRAFTNAV_PYTHON");
        const std::string py = env ? env
                               : std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3"
                                                                             : "python3";
        const std::string cmdline = fmt::format("'{}' '{}' '{}'", py, script, args->out);
        if (std::system(cmdline.c_str()) != 0)
          fmt::print(stderr, "warning: plotting failed ({}); the numbers are written\n", cmdline);
      }
    }
  });
}

}  // namespace graftnav::app
