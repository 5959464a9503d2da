// graftnav graft CASE_DIR [--out DIR] [--seed N] [--no-cross-axis]
// Lab calibration of the tested IMU, then SG#1 and SG#2 grafted onto the reference IMU
// (IMU_SG1.txt, IMU_SG2.txt).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/io/case_config.h"
#include "graftnav/sg/graft_case.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {

void registerGraft(CLI::App& app) {
  struct Args {
    std::string case_dir, out;
    std::uint64_t seed = 1;
    bool no_cross_axis = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "graft", "Write IMU_SG1.txt (SG#1, basic errors) and IMU_SG2.txt (SG#2, full errors)");
  cmd->add_option("case_dir", args->case_dir, "case directory")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", args->out, "output directory (default CASE_DIR/graft)");
  cmd->add_option("--seed", args->seed,
                  "seed choosing where the field test starts in the tiled lab record")
      ->capture_default_str();
  cmd->add_flag("--no-cross-axis", args->no_cross_axis,
                "SG#2 with per-axis fitting functions only, as in the seed (no non-orthogonality)");
  cmd->callback([args]() {
    const std::string out = args->out.empty() ? args->case_dir + "/graft" : args->out;
    std::filesystem::create_directories(out);
    const CasePaths paths(args->case_dir);
    std::vector<std::string> warnings;
    const CaseConfig cfg = loadCaseConfig(paths.caseYaml(), &warnings);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);

    fmt::print(stderr, "graft: calibrating the tested IMU from {}/lab\n", args->case_dir);
    const LabData lab = loadLabData(args->case_dir);
    if (lab.has_static) checkLabStaticRecord(lab.staticRecordSeconds(), lab.static_file, 0.0);
    const LabCalibrationReport report = calibrateLab(lab);
    for (const auto& n : report.notes) fmt::print(stderr, "note: {}\n", n);
    writeCalibrationYaml(out + "/calibration.yaml", report.result);

    ImuReadOptions ro;
    ro.nominal_rate_hz = cfg.imu_rate_hz;
    const ImuSeries ref = readImu(paths.refImu(), ro);
    GraftCaseOptions go;
    go.graft.seed = args->seed;
    go.use_cross_axis = !args->no_cross_axis;
    const GraftedCase g = graftCase(ref, report, go);
    writeImu(out + "/IMU_SG1.txt", g.sg1);
    writeImu(out + "/IMU_SG2.txt", g.sg2);

    fmt::print("grafted {} reference samples ({:.1f} s) -> {}/IMU_SG1.txt, {}/IMU_SG2.txt\n",
               ref.size(), ref.back().t_s - ref.front().t_s + ref.front().dt_s, out, out);
    fmt::print(
        "  basic error signal: static record {:.1f} s, mirrored tiling over {} record lengths, "
        "start offset {:.2f} s (seed {})\n",
        g.static_record_s, g.tiles, g.start_offset_s, args->seed);
    const auto& bg = report.basic.gyro_mean_rad_s;
    const auto& ba = report.basic.accel_mean_m_s2;
    fmt::print(
        "  basic biases: gyro [{:.3f} {:.3f} {:.3f}] deg/h, accel [{:.3f} {:.3f} {:.3f}] mg\n",
        bg.x() / units::kDegPerHourToRadPerSec, bg.y() / units::kDegPerHourToRadPerSec,
        bg.z() / units::kDegPerHourToRadPerSec, ba.x() / units::kMilliGToMPerSec2,
        ba.y() / units::kMilliGToMPerSec2, ba.z() / units::kMilliGToMPerSec2);
    if (cfg.reference_imu && cfg.tested_imu && cfg.reference_imu_noise_given &&
        cfg.tested_imu_noise_given) {
      const Eigen::Vector2d f = referenceResidualFraction(*cfg.reference_imu, *cfg.tested_imu);
      fmt::print(
          "  reference IMU's own white noise grafted along: {:.2f} % (gyro), {:.2f} % (accel) "
          "of the tested IMU's\n",
          100.0 * f[0], 100.0 * f[1]);
    }
    fmt::print("  calibration: {}/calibration.yaml\n", out);
  });
}

}  // namespace graftnav::app
