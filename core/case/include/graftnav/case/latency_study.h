#pragma once
// The GNSS time-tag latency study of `graftnav real --latency-scan / --latency-grid`: the latency
// per fix type against a track made without those fixes and against the case's reference
// solution (estimateGnssLatency, graftnav/eval/gnss_latency.h), and the outage errors with the
// RTK epochs' time tags corrected by each latency of a grid. Each returns its section of
// summary.md; progress goes to `log`.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/eval/evaluation.h"

namespace graftnav {

using StudyLog = std::function<void(const std::string&)>;

struct LatencyStudyOptions {
  // The scan's track uses only these fix types (single point: independent of the RTK epochs
  // whose latency is scanned); then each of scan_fix_types is scanned against it, with residuals
  // beyond outlier_m (single point: outlier_single_m) dropped.
  std::vector<int> track_fix_types{1};
  std::vector<int> scan_fix_types{4, 5, 1};
  double outlier_m = 3.0, outlier_single_m = 10.0;
  // The grid: latencies (s) applied to grid_fix_types, each navigated by grid_estimators.
  std::vector<double> grid;
  std::vector<int> grid_fix_types{4, 5};
  std::vector<std::string> grid_estimators{"ekf", "rts"};
};

// The solution against the case's reference (none when it has none; a failure is logged as a
// warning and gives none).
std::optional<Evaluation> evaluateAgainstReference(const NavSolution& sol, const NavSeries& ref,
                                                   const std::vector<TimeWindow>& outages,
                                                   const RunConfig& rc, const StudyLog& log);

// The scan; writes out_dir/latency_track_rts_fix1.nav and out_dir/latency_scan.csv.
std::string latencyScanMd(const CaseInputs& c, const RunConfig& rc, const EstimationProblem& pr,
                          const LatencyStudyOptions& options, const EstimatorRegistry& estimators,
                          const std::string& out_dir, const StudyLog& log);

// The grid.
std::string latencyGridMd(const CaseInputs& c, const RunConfig& rc, const ImuSelection& imu,
                          const LatencyStudyOptions& options, const EstimatorRegistry& estimators,
                          const StudyLog& log);

}  // namespace graftnav
