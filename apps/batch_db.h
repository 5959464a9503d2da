#pragma once
// The batch results database (SQLite; schema in docs/batch.md).
//
// Concurrency: one file per task. Every finished task writes <task folder>/task.sqlite (to a
// temporary name, renamed when complete, so a killed task leaves no record), and collecting
// merges the task files of the manifest into <out>/results.sqlite, written the same way. No two
// processes ever write one database file, which is what cluster file systems (NFS, Lustre)
// need: SQLite's WAL mode relies on shared memory that they do not provide.
#include <optional>
#include <string>
#include <vector>

#include "batch_task.h"

namespace graftnav::app {

// Where a task stands: ran to the end, ran and failed (its message recorded), or no record of
// its current id (never ran, killed, or its inputs changed since).
enum class TaskStatus { kOk, kFailed, kMissing };
// "ok", "failed", "missing": the words of runs.status and of the summaries.
const char* statusName(TaskStatus s);

// Statistics of one solution (SG1, SG2, REAL, ...) of one run, per statistic (horizontal_m,
// vertical_m, roll_deg, pitch_deg, heading_deg). Angles in degrees, DIFF as a fraction.
struct BatchStatisticRow {
  std::string solution, statistic;
  double outage_rms = 0.0;      // the seed's ERR: RMS over all outage epochs
  double outage_max_rms = 0.0;  // RMS over outages of the per-outage maximum
  double overall_rms = 0.0;     // RMS over all evaluated epochs
  std::optional<double> diff;   // |ERR_x - ERR_REAL| / ERR_REAL, when REAL exists
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

struct BatchRunRecord {
  bool ok = false;
  std::string error;  // why it failed
  std::optional<int> outage_count;
  std::string reference;
  double seconds = 0.0;
  std::vector<BatchStatisticRow> statistics;
  std::vector<BatchOutageRow> outages;
  std::optional<int> realizations;  // K of predictive grafting, when it ran
  std::vector<BatchPredictiveRow> predictive;
};

// What predictive grafting added to evaluation.json, when present (nothing otherwise): the
// number "realizations" (K) and the "predictive" object, solution -> statistic -> numbers:
//   "predictive": {"SG1": {"horizontal_m": {"p05": .., "p50": .., "p95": .., "mean": .., "sd": ..,
//                                           "real_percentile": .., "verdict": ".."}, ...}, ...}
// Missing numbers stay NULL. Throws naming the file when it is not valid JSON.
struct BatchPredictive {
  std::optional<int> realizations;
  std::vector<BatchPredictiveRow> rows;
};
BatchPredictive readPredictive(const std::string& evaluation_json_path);

// Writes the task's database atomically (a previous one is replaced only when complete).
void writeTaskDatabase(const std::string& path, const BatchTask& task,
                       const BatchRunRecord& record);

// kOk or kFailed when `path` holds a record of the task with this id, kMissing otherwise (no
// file, another id, an unreadable file).
TaskStatus taskDatabaseStatus(const std::string& path, const std::string& task_id);

struct CollectCounts {
  int ok = 0, failed = 0, missing = 0;
};

// Builds <out_db_path> from scratch: the manifest's tasks, and every task database that records
// the task's current id. Written atomically.
CollectCounts collectTaskDatabases(const std::string& out_db_path,
                                   const std::vector<BatchTask>& tasks);

// One row of the summaries: a task and, when it ran, its status and statistics.
struct BatchSummaryRow {
  int task_index = 0;
  std::string case_name, estimator, schedule;
  unsigned long long seed = 0;
  TaskStatus status = TaskStatus::kMissing;
  std::string error;
  std::optional<int> outage_count;
  std::vector<BatchStatisticRow> statistics;
};

// The summary rows in task order, read from a collected database.
std::vector<BatchSummaryRow> readSummaryRows(const std::string& db_path);

}  // namespace graftnav::app
