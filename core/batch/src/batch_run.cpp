#include "graftnav/batch/batch_run.h"

#include <fmt/core.h>

#include <chrono>
#include <filesystem>

#include "graftnav/batch/child_process.h"
#include "graftnav/batch/fleet_report.h"
#include "graftnav/batch/summary.h"
#include "graftnav/batch/task_outputs.h"
#include "graftnav/parallel/worker_pool.h"

namespace graftnav {
namespace fs = std::filesystem;
namespace {

// Temporary files a killed run of this task left in its folder (hidden ".<name>.tmp.*", the
// atomic writers' pattern). The folder belongs to this task only, so they are the task's own.
void removeStaleTemporaries(const BatchTask& t) {
  if (!fs::is_directory(t.out_dir)) return;
  for (const auto& e : fs::directory_iterator(t.out_dir)) {
    const std::string n = e.path().filename().string();
    if (n.size() > 1 && n[0] == '.' && n.find(".tmp.") != std::string::npos) fs::remove(e.path());
  }
}

// The grafted IMU files evaluate writes beside its tables (realization 0 of SG#1 and SG#2, the
// size of the field IMU each): a batch keeps tables, `graftnav evaluate` on one case keeps these.
void removeGraftedImu(const BatchTask& t) {
  if (t.command != BatchCommand::kEvaluate) return;
  for (const char* f : {"IMU_SG1.txt", "IMU_SG2.txt"}) fs::remove(fs::path(t.out_dir) / f);
}

std::string failureMessage(const ChildResult& c, const std::string& log_path) {
  const std::string tail = lastLines(log_path, 3);
  std::string msg = fmt::format("`graftnav` {}", c.describe());
  return tail.empty() ? msg + " and wrote nothing on stderr" : msg + ": " + tail;
}

}  // namespace

std::string taskDatabasePath(const BatchTask& t) {
  return (fs::path(t.out_dir) / "task.sqlite").string();
}

BatchRunRecord runBatchTask(const BatchManifest& m, const BatchTask& t, const std::string& exe) {
  BatchRunRecord rec;
  fs::create_directories(t.out_dir);
  removeStaleTemporaries(t);
  const std::string log_path = (fs::path(t.out_dir) / "log.txt").string();
  try {
    writeTaskRunConfig(m, t);
    const ChildResult c = runChildProcess(taskCommandLine(m, t, exe), t.out_dir,
                                          (fs::path(t.out_dir) / "stdout.txt").string(), log_path);
    rec.seconds = c.wall_seconds;
    rec.peak_rss_mb = c.peak_rss_mb;
    rec.cpu_seconds = c.cpu_seconds;
    if (c.signal == 0) rec.exit_code = c.exit_code;
    if (c.ok()) {
      rec.ok = true;
      readTaskOutputs(t.command, t.out_dir, t.estimators, &rec);
    } else {
      rec.error = failureMessage(c, log_path);
    }
    removeGraftedImu(t);
  } catch (const std::exception& e) {
    rec.ok = false;
    rec.error = e.what();
  }
  if (!rec.ok) {  // no half-read rows next to a failure
    rec.statistics.clear();
    rec.outages.clear();
    rec.predictive.clear();
    rec.effects.clear();
    rec.cross_checks.clear();
  }
  writeTaskDatabase(taskDatabasePath(t), t, rec);
  return rec;
}

BatchRunCounts runBatchTasks(const BatchManifest& m, const std::vector<BatchTask>& tasks,
                             const std::vector<std::size_t>& which, const std::string& exe,
                             int jobs, bool force, const BatchLogFn& log) {
  std::vector<const BatchTask*> todo;
  BatchRunCounts n;
  for (std::size_t i : which) {
    const BatchTask& t = tasks.at(i);
    if (!force && taskDatabaseStatus(taskDatabasePath(t), t.id) == TaskStatus::kOk)
      ++n.skipped;
    else
      todo.push_back(&t);
  }
  const int workers = workerCount(todo.size(), jobs);
  log(fmt::format("batch: {} of {} tasks: {} finished before, {} to run on {} worker(s)",
                  which.size(), tasks.size(), n.skipped, todo.size(), workers));
  std::vector<std::string> errors(todo.size());
  const auto t0 = std::chrono::steady_clock::now();
  auto run = [&](std::size_t i) {
    try {
      const BatchRunRecord r = runBatchTask(m, *todo[i], exe);
      if (!r.ok) errors[i] = r.error;
    } catch (const std::exception& e) {  // the record itself could not be written
      errors[i] = std::string("no record written: ") + e.what();
    }
  };
  auto report = [&](std::size_t i, std::size_t done) {
    const BatchTask& t = *todo[i];
    if (!errors[i].empty()) ++n.failed;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::string e = errors[i];
    std::replace(e.begin(), e.end(), '\n', ' ');
    log(fmt::format("[{}/{}] {:.0f} s  task {} {} {}: {}", done, todo.size(), el, t.index, t.id,
                    t.folder(), e.empty() ? "ok" : "FAILED (" + e + ")"));
  };
  parallelFor(todo.size(), workers, run, report);
  n.ran = static_cast<int>(todo.size());
  return n;
}

CollectCounts collectBatch(const BatchManifest& m, const std::vector<BatchTask>& tasks) {
  fs::create_directories(m.out_dir);
  const std::string db = (fs::path(m.out_dir) / "results.sqlite").string();
  const CollectCounts c = collectTaskDatabases(db, tasks);
  writeBatchReports(m.out_dir);
  return c;
}

void writeBatchReports(const std::string& out_dir) {
  const std::vector<BatchTaskResult> rows =
      readBatchResults((fs::path(out_dir) / "results.sqlite").string());
  writeBatchSummaries(out_dir, rows);
  writeFleetReports(out_dir, rows);
}

}  // namespace graftnav
