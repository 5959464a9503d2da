#pragma once
// The main job: calibrate the tested IMU from its lab data, graft K realizations of SG#1 and SG#2
// onto the reference field IMU (sg/realization.h), navigate each and (when recorded) the real
// tested IMU with one outage schedule, optionally repeated at N shifted starts, and compare their
// errors against SOL_REF (truth, an external reference, or the smoothed reference IMU). ERR_SGx is
// the mean over realizations; the realizations' spread gives the predictive interval in which
// ERR_REAL should fall when grafting lacks no physics (sg/predictive.h). Used by `graftnav
// evaluate` and, in-process, by `graftnav batch`.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/sg/sg_report_files.h"

namespace graftnav::app {

struct SgEvaluateOptions {
  std::string case_dir;
  std::string out_dir;
  std::string estimator = "ekf";
  std::string run_config;  // --run-config YAML (graftnav/case/run_config.h); empty: defaults
  std::optional<double> outage_length_s, outage_period_s, outage_start_s;
  std::optional<int> realizations;   // K; default from the run config (20)
  std::optional<int> outage_shifts;  // N; default from the run config (1)
  std::string sol_ref =
      "auto";  // auto: truth > reference_solution > smoothed; "smooth": always smooth
  std::uint64_t seed = 1;
  bool use_cross_axis = true;
  bool write_grafted_imu = true;  // IMU_SG1.txt / IMU_SG2.txt (realization 0) in out_dir
  bool plots = true;
  int jobs = 0;  // navigations in parallel; 0 = all cores
};

using LogFn = std::function<void(const std::string&)>;

// Every check of graftnav/case/input_checks.h for this evaluation, run before anything is
// written: estimator name, outage options, the case's files (IMU range checks in the reader),
// GNSS coverage, outages inside the data and the reference, the lab static record. Returns the
// warnings; throws on the first error.
std::vector<std::string> checkEvaluationInputs(const SgEvaluateOptions& options);

// Throws std::runtime_error naming the file or key for a bad case (missing lab file, mismatched
// rates, no reference, no outage inside the data, ...) before writing any result. Writes
// evaluation.json, tables.md, evaluation.csv, predictive.csv, outage_drift.csv,
// errors_<LABEL>.csv and plots into out_dir.
SgEvaluationReport runSgEvaluation(const SgEvaluateOptions& options, const LogFn& log = {});

// The console summary of `evaluate` and `real-sg`: ERR with intervals, REAL's percentile and
// verdict, DIFF and the reading sentences (cmd_evaluate.cpp).
void printEvaluationSummary(const SgEvaluationReport& report);

// evaluation.json, tables.md, evaluation.csv, predictive.csv, outage_drift.csv, errors_<LABEL>.csv
// and (plots) the plots of a report into out_dir (shared with `real-sg`). errors_csv false: the
// errors_<LABEL>.csv were written as the epochs came (the report holds no epochs).
void writeSgOutputs(const std::string& out_dir, const SgEvaluationReport& report, bool plots,
                    const LogFn& log, bool errors_csv = true);

}  // namespace graftnav::app
