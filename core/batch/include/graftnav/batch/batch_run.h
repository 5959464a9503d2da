#pragma once
// Running a manifest's tasks: each as a `graftnav <command>` child process, on the worker pool,
// skipping those already finished, each recorded in its own task database; then collecting the
// task databases into results.sqlite and writing the summaries and fleet reports from it.

#include <functional>
#include <string>
#include <vector>

#include "graftnav/batch/results_db.h"
#include "graftnav/batch/tasks.h"

namespace graftnav {

using BatchLogFn = std::function<void(const std::string&)>;

// <task folder>/task.sqlite
std::string taskDatabasePath(const BatchTask& task);

// Runs one task (its run config written first) as a child process in its folder: stdout into
// stdout.txt, stderr into log.txt. A non-zero exit or a crash makes the task failed with the exit
// status and the last lines of log.txt as its message; after a clean exit the command's result
// files are read (task_outputs.h). Records the result, ok or failed, in the task database and
// returns it. Throws only when the record cannot be written.
BatchRunRecord runBatchTask(const BatchManifest& manifest, const BatchTask& task,
                            const std::string& graftnav_exe);

struct BatchRunCounts {
  int ran = 0, skipped = 0, failed = 0;
};

// Runs tasks[i] for every i in `which` on `jobs` workers (0: all cores), skipping those whose
// database records their current id as ok unless `force`. A failed task is recorded and the
// others go on; one progress line per task goes to `log`.
BatchRunCounts runBatchTasks(const BatchManifest& manifest, const std::vector<BatchTask>& tasks,
                             const std::vector<std::size_t>& which, const std::string& graftnav_exe,
                             int jobs, bool force, const BatchLogFn& log);

// <out>/results.sqlite built from the task databases, then the summaries and fleet reports.
CollectCounts collectBatch(const BatchManifest& manifest, const std::vector<BatchTask>& tasks);
// The summaries and fleet reports again from <out>/results.sqlite.
void writeBatchReports(const std::string& out_dir);

}  // namespace graftnav
