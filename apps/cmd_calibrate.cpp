// graftnav calibrate CASE_DIR --out OUT_DIR [--gravity G] [--max-degree N] [--no-plots]
// graftnav calibrate --raw-counts ACC GYRO --out OUT_DIR   (multi-position, imu_tk text files)
// graftnav calibrate --multi-position IMU.txt --out OUT_DIR (multi-position, graftnav IMU file)
//
// Writes OUT_DIR/calibration.yaml (see calibration_io.h), OUT_DIR/report.md, CSV tables and, when
// python3 + matplotlib are available, PNG plots made by scripts/runtime/plot_allan.py and
// scripts/runtime/plot_calibration.py.
#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "script_locator.h"
#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/calibration_report.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/multi_position.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {
namespace {

namespace fs = std::filesystem;

struct CalibArgs {
  std::string case_dir, out, multi_position, scripts_dir;
  std::vector<std::string> raw_counts;
  double gravity = 0.0;
  double init_static_s = 0.0;
  int max_degree = 3;
  bool no_plots = false;
};

// Plots through the shared script runner (scripts dir and python with matplotlib found once).
void runPlot(const std::string& script, const std::string& out, std::vector<std::string>& made) {
  const std::string w = runPythonScript(script, {out});
  if (!w.empty()) {
    fmt::print(stderr, "warning: {}\n", w);
  } else {
    made.push_back(script);
  }
}

void runLab(const CalibArgs& a) {
  LabDataOptions lo;
  lo.gravity_override_m_s2 = a.gravity;
  const LabData data = loadLabData(a.case_dir, lo);
  for (const auto& w : data.warnings) fmt::print(stderr, "warning: {}\n", w);
  // The floor `evaluate` applies: a shorter record gives no usable basic error signal or Allan.
  if (data.has_static) checkLabStaticRecord(data.staticRecordSeconds(), data.static_file, 0.0);
  LabCalibrationOptions co;
  co.poly.max_degree = a.max_degree;
  const LabCalibrationReport rep = calibrateLab(data, co);
  fs::create_directories(a.out);
  writeCalibrationYaml(a.out + "/calibration.yaml", rep.result);
  writeLabCalibrationTables(a.out, data, rep);
  std::vector<std::string> plots;
  if (!a.no_plots) {
    if (!a.scripts_dir.empty()) setenv("GRAFTNAV_SCRIPTS_DIR", a.scripts_dir.c_str(), 1);
    if (rep.has_allan) runPlot("plot_allan.py", a.out, plots);
    runPlot("plot_calibration.py", a.out, plots);
  }
  writeFileAtomically(a.out + "/report.md",
                      labCalibrationMarkdown(a.case_dir, a.out, data, rep, co, !plots.empty()));
  fmt::print("calibrated '{}' -> {}/calibration.yaml\n", data.name, a.out);
  if (rep.has_accel)
    fmt::print("  accel: |f|-g RMS {:.5f} -> {:.5f} m/s^2 over {} poses\n", rep.norm_rms_before,
               rep.norm_rms_after, rep.norm_checks.size());
  if (rep.has_allan)
    for (int i = 0; i < 3; ++i)
      fmt::print("  gyro {}: ARW {:.4f} deg/sqrt(h), BI {:.3f} deg/h\n", char('x' + i),
                 rep.result.gyro.allan.white_noise[i] * units::kRadToDeg * 60.0,
                 rep.result.gyro.allan.bias_instability[i] * units::kRadToDeg * 3600.0);
  for (const auto& n : rep.notes) fmt::print("  note: {}\n", n);
}

void runMultiPosition(const CalibArgs& a) {
  MultiPositionOptions o;
  o.gravity_m_s2 = a.gravity > 0.0 ? a.gravity : 9.80665;
  o.detector.init_static_s = a.init_static_s;
  ImuSeries imu;
  std::string src;
  if (!a.raw_counts.empty()) {
    imu = readRawCountPair(a.raw_counts[0], a.raw_counts[1]);
    src = a.raw_counts[0];
  } else {
    ImuReadOptions ro;
    ro.policy = ImuReadPolicy::real();
    imu = readImu(a.multi_position, ro);
    src = a.multi_position;
  }
  const MultiPositionResult r = calibrateMultiPosition(imu, o, src);
  CalibrationResult res;
  res.case_name = fs::path(src).stem().string();
  res.gravity_m_s2 = o.gravity_m_s2;
  res.accel = r.accel;
  res.gyro = r.gyro;
  fs::create_directories(a.out);
  writeCalibrationYaml(a.out + "/calibration.yaml", res);
  writeMultiPositionReport(a.out, src, r, o.gravity_m_s2, a.gravity > 0.0);
  fmt::print("multi-position calibration of {} -> {}/calibration.yaml\n", src, a.out);
  fmt::print(
      "  {} static intervals; |f|-g RMS {:.5f} -> {:.5f} m/s^2; gravity direction RMS {:.3f} -> {:.3f} deg\n",
      r.intervals.size(), r.accel_norm_rms_before, r.accel_norm_rms_after,
      r.gyro_angle_rms_before * units::kRadToDeg, r.gyro_angle_rms_after * units::kRadToDeg);
  for (const auto& n : r.notes) fmt::print("  note: {}\n", n);
}

}  // namespace

void registerCalibrate(CLI::App& app) {
  auto a = std::make_shared<CalibArgs>();
  CLI::App* cmd = app.add_subcommand("calibrate",
                                     "Lab calibration of the tested IMU (six-position, rate table, "
                                     "basic errors, Allan, fitting functions) or multi-position");
  cmd->add_option("case_dir", a->case_dir, "case directory (case.yaml + lab/)");
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--gravity", a->gravity,
                  "gravity magnitude m/s^2 (default: normal gravity at the lab, "
                  "9.80665 when the latitude is unknown)");
  cmd->add_option("--max-degree", a->max_degree, "largest fitting-function degree (1..4)")
      ->check(CLI::Range(1, 4));
  cmd->add_flag("--no-plots", a->no_plots, "do not run the matplotlib scripts");
  cmd->add_option("--scripts-dir", a->scripts_dir, "where plot_allan.py / plot_calibration.py are");
  cmd->add_option("--multi-position", a->multi_position,
                  "multi-position recording (graftnav IMU file)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--raw-counts", a->raw_counts,
                  "multi-position recording as two imu_tk count files ACC GYRO")
      ->expected(2)
      ->check(CLI::ExistingFile);
  cmd->add_option(
      "--init-static", a->init_static_s,
      "multi-position: seconds of initial static data for adaptive detector thresholds");
  cmd->callback([a]() {
    const int modes = !a->case_dir.empty() + !a->multi_position.empty() + !a->raw_counts.empty();
    if (modes != 1)
      throw CLI::ValidationError("calibrate",
                                 "give exactly one of CASE_DIR, --multi-position, --raw-counts");
    if (!a->case_dir.empty())
      runLab(*a);
    else
      runMultiPosition(*a);
  });
}

}  // namespace graftnav::app
