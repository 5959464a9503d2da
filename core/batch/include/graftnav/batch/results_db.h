#pragma once
// The batch results database (SQLite, schema version 2; docs/batch.md describes every table).
//
// Concurrency: one file per task. Every finished task writes <task folder>/task.sqlite (to a
// temporary name, renamed when complete, so a killed task leaves no record), and collecting
// merges the task files of the manifest into <out>/results.sqlite, written the same way. No two
// processes ever write one database file, which is what cluster file systems (NFS, Lustre)
// need: SQLite's WAL mode relies on shared memory that they do not provide.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/batch/run_record.h"
#include "graftnav/batch/tasks.h"

namespace graftnav {

// The schema this graftnav writes and reads.
inline constexpr int kBatchSchemaVersion = 2;

// Writes the task's record into a new database at `path` (atomically).
void writeTaskDatabase(const std::string& path, const BatchTask& task,
                       const BatchRunRecord& record);

// The status recorded for `task_id` in the task file at `path`: kMissing when there is no file,
// another task's or another schema version's record, or an unreadable file (the task then runs
// again and replaces it).
TaskStatus taskDatabaseStatus(const std::string& path, const std::string& task_id);

// The peak RSS (MiB) the task file records of a finished run (of any id: an earlier run of the
// task is as good a measure), if any.
std::optional<double> taskPeakRssMb(const std::string& path);

struct CollectCounts {
  int ok = 0, failed = 0, missing = 0;
};

// Builds `out_db_path` afresh: every task of the manifest, and the results of every task whose
// folder holds a task.sqlite recording its current id. Throws naming the file and its version
// when a task file of another schema version records the task.
CollectCounts collectTaskDatabases(const std::string& out_db_path,
                                   const std::vector<BatchTask>& tasks);

// One task of a collected database, with what the summaries and reports read of it.
struct BatchTaskResult {
  int task_index = 0;
  std::string task_id, name, grp, case_name, estimator, schedule, options_json;
  BatchCommand command = BatchCommand::kEvaluate;
  std::optional<unsigned long long> seed;
  TaskStatus status = TaskStatus::kMissing;
  std::string error;
  std::optional<int> outage_count;
  std::vector<BatchStatisticRow> statistics;
  std::vector<BatchCrossCheckRow> cross_checks;
  int effects = 0;  // effect parameters recorded (diagnose)
};

// Every task in index order. Throws naming the file and its version when it is not a schema-2
// database (a schema-1 file: rebuild it with --collect).
std::vector<BatchTaskResult> readBatchResults(const std::string& db_path);

// The schema version a database file records (0 when it records none).
int databaseSchemaVersion(const std::string& db_path);

}  // namespace graftnav
