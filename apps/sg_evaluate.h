#pragma once
// The main job: calibrate the tested IMU from its lab data, graft SG#1 and SG#2 onto the reference
// field IMU, navigate SG#1, SG#2 and (when recorded) the real tested IMU with one outage schedule,
// and compare their errors against SOL_REF (truth, an external reference, or the smoothed
// reference IMU). Used by `graftnav evaluate` and, in-process, by `graftnav batch`.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "sg_report.h"

namespace graftnav::app {

struct SgEvaluateOptions {
  std::string case_dir;
  std::string out_dir;
  std::string estimator = "ekf";
  std::string config_path;  // --config YAML (run_config.h); empty: defaults
  std::optional<double> outage_length_s, outage_period_s, outage_start_s;
  std::string sol_ref = "auto";  // auto: truth > reference_solution > smoothed; "smooth": always smooth
  std::uint64_t seed = 1;
  bool use_cross_axis = true;
  bool write_grafted_imu = true;  // IMU_SG1.txt / IMU_SG2.txt in out_dir
  bool plots = true;
  int jobs = 0;  // solutions navigated in parallel; 0 = all cores
};

using LogFn = std::function<void(const std::string&)>;

// Throws std::runtime_error naming the file or key for a bad case (missing lab file, mismatched
// rates, no reference, ...). Writes evaluation.json, tables.md, evaluation.csv,
// outage_drift.csv, errors_<LABEL>.csv and plots into out_dir.
SgEvaluationReport runSgEvaluation(const SgEvaluateOptions& options, const LogFn& log = {});

}  // namespace graftnav::app
