#pragma once
// The SG evaluation of a case folder, the main job: calibrate the tested IMU from its lab data,
// graft K realizations of SG#1 and SG#2 onto the reference field IMU (graftnav/sg/grafting.h),
// navigate each and (when recorded) the real tested IMU with one outage schedule, optionally
// repeated at N shifted starts, and compare their errors against SOL_REF (truth, an external
// reference, or the smoothed reference IMU). ERR_SGx is the mean over realizations; their spread
// gives the predictive interval in which ERR_REAL should fall when grafting lacks no physics.
//
// The estimators come from the registry the caller hands in (the command and the Python module
// hand the full table). When the estimator and the smoother have streamed forms and the
// alignment is given, nothing that grows with the recording is held: the IMU files are spooled
// once, each realization is grafted block by block and every solution is evaluated as it comes.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/sg/evaluate_pipeline.h"
#include "graftnav/sg/sg_evaluation_report.h"

namespace graftnav {

struct SgCaseEvaluationOptions {
  std::string case_dir;
  std::string out_dir;  // calibration.yaml, IMU_SG1/2.txt and streamed errors_<LABEL>.csv
  std::string estimator = "ekf";
  std::string run_config;  // run-config YAML (graftnav/case/run_config.h); empty: defaults
  std::optional<double> outage_length_s, outage_period_s, outage_start_s;
  std::optional<int> realizations;     // K; default from the run config (20)
  std::optional<int> outage_shifts;    // N; default from the run config (1)
  bool always_smooth_sol_ref = false;  // false: truth > reference_solution > smoothed
  std::uint64_t seed = 1;
  bool use_cross_axis = true;
  bool write_grafted_imu = true;  // IMU_SG1.txt / IMU_SG2.txt (realization 0) in out_dir
  int jobs = 0;                   // navigations in parallel; 0 = all cores
};

struct SgCaseEvaluation {
  SgEvaluationReport report;
  bool errors_csv_written = false;  // errors_<LABEL>.csv written as the epochs came (streamed)
};

// Every check of graftnav/case/input_checks.h for this evaluation, run before anything is
// written: estimator name, outage options, the case's files (IMU range checks in the reader),
// GNSS coverage, outages inside the data and the reference, the lab static record. Returns the
// warnings; throws on the first error.
std::vector<std::string> checkSgCaseInputs(const SgCaseEvaluationOptions& options,
                                           const EstimatorRegistry& estimators);

// Checks, then runs the evaluation, writing calibration.yaml, the grafted IMU files and (when
// streamed) the errors_<LABEL>.csv into out_dir. The report's files are the caller's
// (graftnav/sg/sg_report_files.h). Throws std::runtime_error naming the file or key for a bad
// case before writing anything.
SgCaseEvaluation runSgCaseEvaluation(const SgCaseEvaluationOptions& options,
                                     const EstimatorRegistry& estimators, const SgLogFn& log = {});

// The pieces for a caller that holds the case in memory (the Python module):
// the tested IMU must carry its noise parameters to be navigated (throws naming case.yaml);
void requireTestedNoise(const CaseInputs& c);
// the pipeline's options from the run config and the request;
SgEvaluationOptions sgPipelineOptions(const RunConfig& rc, std::optional<int> realizations,
                                      std::optional<int> outage_shifts, std::uint64_t seed,
                                      int jobs);
// the pipeline's inputs from the case and the lab calibration (the reference IMU is the
// caller's to set: held or spooled);
SgEvaluationInputs sgPipelineInputs(const std::string& case_name, const CaseInputs& c,
                                    const OutageScheduleConfig& outages,
                                    const LabCalibrationReport& lab);
// the case's navigator over held series: makeProblem with the tested IMU's profile for a
// grafted IMU, or the real tested IMU's selection, then the estimator. `c`, `rc`, `real` and
// `estimators` must outlive it.
SgNavigator heldCaseNavigator(const CaseInputs& c, const RunConfig& rc, const ImuSelection* real,
                              const EstimatorRegistry& estimators, const std::string& estimator);

}  // namespace graftnav
