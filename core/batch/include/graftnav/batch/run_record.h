#pragma once
// What one finished task gives the results database: its status and the rows read from the
// files its command wrote (task_outputs.h). Units are in the names: m, deg, fractions.

#include <optional>
#include <string>
#include <vector>

namespace graftnav {

// Where a task stands: ran to the end, ran and failed (its message recorded), or no record of
// its current id (never ran, killed, or its inputs changed since).
enum class TaskStatus { kOk, kFailed, kMissing };
// "ok", "failed", "missing": the words of runs.status and of the summaries.
const char* statusName(TaskStatus s);

// One number of one solution. `scope` is the set of epochs: overall (every evaluated epoch),
// outage (inside the GNSS outages), checkpoint (withheld GNSS check points inside the outages),
// reference (inside the outages, against the case's reference solution: `real`). `statistic`
// names the quantity (horizontal_m, vertical_m, roll_deg, pitch_deg, heading_deg, nees, points),
// `measure` the reduction: rms, max_rms (RMS over outages of the per-outage maximum), diff
// (|ERR_x - ERR_REAL| / ERR_REAL), mean, count.
struct BatchStatisticRow {
  std::string estimator, solution, scope, statistic, measure;
  double value = 0.0;
  std::string unit;  // m, deg, frac, 1
};

// One outage of one solution: the maximum of each absolute error inside it.
struct BatchOutageRow {
  std::string solution;
  int outage_index = 0;
  double start_s = 0.0, end_s = 0.0;  // GNSS seconds of week
  int epochs = 0;
  double horizontal_m = 0.0, vertical_m = 0.0, roll_deg = 0.0, pitch_deg = 0.0, heading_deg = 0.0;
};

// Predictive grafting: the spread of a statistic over K grafted realizations.
struct BatchPredictiveRow {
  std::string solution, statistic;
  std::optional<double> p05, p50, p95, mean, sd, real_percentile;
  std::optional<std::string> verdict;
};

// One parameter of one effect the mismatch finder reported (diagnose). kind: claimed, ambiguous,
// implausible. A list parameter gives one row per element ("scale[2]"); a text one has no value.
struct BatchEffectRow {
  std::string kind, name, sensor, parameter;
  std::optional<double> value, sigma;
  std::string text;
};

// One estimator pair of a compare task inside the outages (cross_check.h in core/eval): the
// difference and, when both give sigmas, the difference weighed by its own sigma.
struct BatchCrossCheckRow {
  std::string a, b;
  std::string sigma_form;  // filter-smoother, sum-upper-bound, or none (a or b gives no sigma)
  std::string statistic;   // horizontal_m, vertical_m, heading_deg
  std::optional<double> rms_difference, rms_sigma, rms_normalized, max_normalized;
  int epochs = 0;
};

struct BatchRunRecord {
  bool ok = false;
  std::string error;  // why it failed (empty when ok)
  std::optional<int> outage_count;
  std::string reference;  // what the errors are against (SOL_REF, truth, reference.nav ...)
  double seconds = 0.0;   // wall time of the task
  std::optional<double> peak_rss_mb, cpu_seconds;  // of the task's process (wait4)
  std::optional<int> exit_code;
  std::optional<int> realizations;
  std::vector<BatchStatisticRow> statistics;
  std::vector<BatchOutageRow> outages;
  std::vector<BatchPredictiveRow> predictive;
  std::vector<BatchEffectRow> effects;
  std::vector<BatchCrossCheckRow> cross_checks;
};

}  // namespace graftnav
