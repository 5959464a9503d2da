#pragma once
// `graftnav compare`: several estimators on one case, each evaluated against the reference and
// each pair compared inside the outages (the difference and the cross-check weighed by sigma).
// When every estimator has a streamed form (a data alignment reads the samples it needs:
// streamed_problem.h), the IMU is read in blocks,
// each solution is evaluated as it comes and written once to a temporary binary spool
// (eval/solution_spool.h), and the pairs are joined from the spools: no solution is held whole.
// Otherwise the IMU is held and the estimators run in memory; the numbers are the same either
// way. A time range (the run config's, with the request's bounds over it) keeps what navigate
// keeps of the IMU and the GNSS (restrictToTimeRange's rule, streamed_imu_file.h when streamed).
#include <functional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/eval/compare_report.h"
#include "graftnav/navigate/navigate_request.h"

namespace graftnav {

// The names compare takes, for --help and messages: the registry's, then "<name>-noearth" for
// each estimator whose Earth rotation is optional.
std::string compareEstimatorNamesText(const EstimatorRegistry& registry);

struct CompareRequest {
  std::string case_dir;
  std::string imu = "ref";   // "ref", "tested" or the path of an IMU file
  std::string profile_path;  // IMU profile YAML; empty: the one case.yaml names
  // Registry names, or "<name>-noearth" for an estimator whose Earth rotation is optional (the
  // factor graphs: omega_ie off in the preintegration, for the Tang et al. comparison).
  std::vector<std::string> estimators{"ekf", "rts", "fgo"};
  std::string run_config;  // run config YAML (ekf:, fgo:, outages:); empty: none
  OutageOverrides outage;  // over the run config's outages: (default 60 s every 180 s from 300 s)
  TimeRangeConfig time_range;  // over the run config's time_range: section
  bool no_outages = false;
  bool lenient = false;
  // Where the solutions are spooled while the pairs are compared (~120 MB per estimator-hour at
  // 200 Hz, unlinked at once): the command's output folder; empty: TMPDIR.
  std::string spool_dir;
};

// The case, the run config and the outage schedule as `navigate` reads them.
struct CompareInputs {
  RunConfig cfg;
  CaseInputs c;  // without its reference: read as a stream
  CaseReferenceFile reference;
  ImuSelection imu;
  long imu_samples = 0;
  bool stream = false;         // the IMU read in blocks by each run (imu.imu and p.imu not held)
  TimeRangeConfig time_range;  // the run config's, with the request's bounds over it
  OutageScheduleConfig schedule;
  EstimationProblem p;
};

// Checks the names and reads the inputs; throws std::runtime_error (an unknown estimator, a case
// without a reference, no noise parameters, outages outside the data).
CompareInputs loadCompareInputs(const CompareRequest& request, const EstimatorRegistry& registry,
                                const RunMessages& messages);

// Runs every estimator and every pair; on_row (may be empty) is called as each estimator ends.
// Throws before any file is written when an estimator used no GNSS.
CompareReport runCompare(const CompareRequest& request, const CompareInputs& inputs,
                         const EstimatorRegistry& registry,
                         const std::function<void(const CompareRow&)>& on_row = {});

}  // namespace graftnav
