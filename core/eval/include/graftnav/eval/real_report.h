#pragma once
// The result files of `graftnav real` (one real recording, several estimators, one outage
// schedule): per estimator the errors at the withheld GNSS check points (checkpoints.csv), and
// for the run summary.json and summary.md's outage tables. docs/outputs.md lists the columns.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/gnss_latency.h"

namespace graftnav {

// One estimator's run on the recording.
struct EstimatorRun {
  std::string label;
  NavSolution sol;
  CheckpointEvaluation cp;
  std::optional<Evaluation> ref;  // against the case's reference solution, when it has one
  double seconds = 0.0;           // run time
};

// v formatted with f, or "-" when it is not finite (a table cell).
std::string formatOrDash(double v, const char* f = "{:.2f}");

// checkpoints.csv: per outage window the check points' count and horizontal/vertical errors.
void writeCheckpointCsv(const std::string& path, const CheckpointEvaluation& cp);

// summary.json: the numbers of summary.md's main table, one object per estimator, plus the run's
// provenance (version, commit, command line, config hashes). Angles in degrees; NaN as null.
void writeRealSummaryJson(const std::string& path, const std::vector<EstimatorRun>& rows,
                          const std::vector<TimeWindow>& outages, int checkpoints_in_outages,
                          const std::vector<std::string>& failed);

// summary.md's main table (check points of checkpoint_fix_types inside the outages, and the
// errors against the reference) and, per outage (seconds after t_first_s), the maximum
// horizontal error at the check points.
std::string realOutageTablesMd(const std::vector<EstimatorRun>& rows,
                               const std::vector<std::string>& failed,
                               const std::vector<TimeWindow>& outages,
                               const std::vector<int>& checkpoint_fix_types, double t_first_s);

}  // namespace graftnav
