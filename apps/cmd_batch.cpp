// graftnav batch MANIFEST.yaml: the manifest's tasks (cases x estimators x outage schedules x
// seeds), run locally in parallel or as a Slurm array, resumable, results in SQLite and summaries
// written from it. docs/batch.md describes the workflow and the database.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>

#include "batch_db.h"
#include "graftnav/io/atomic_file.h"
#include "batch_manifest.h"
#include "batch_slurm.h"
#include "batch_summary.h"
#include "batch_task.h"
#include "commands.h"
#include "graftnav/nav/units.h"
#include "graftnav/parallel/worker_pool.h"
#include "graftnav/sg/sg_statistics.h"
#include "sg_evaluate.h"

namespace graftnav::app {
namespace {
namespace fs = std::filesystem;

struct BatchCli {
  std::string manifest, out;
  int jobs = -1;
  bool list = false, force = false, collect = false, slurm = false, submit = false;
  int task = -1;
  SlurmOptions slurm_options;
};

std::string taskDatabasePath(const BatchTask& t) {
  return (fs::path(t.out_dir) / "task.sqlite").string();
}

// The report's numbers in the database's units (m, deg; DIFF as a fraction).
BatchRunRecord recordOf(const SgEvaluationReport& report) {
  BatchRunRecord rec;
  rec.ok = true;
  rec.outage_count = static_cast<int>(report.outages.size());
  rec.reference = report.reference;
  const auto& names = driftStatNames();
  auto reportUnits = [](std::array<double, 5> a) {
    for (int i = 2; i < 5; ++i) a[i] *= units::kRadToDeg;
    return a;
  };
  for (const auto& s : report.solutions) {
    const auto err = reportUnits(asArray(s.err_rms));  // SG: mean over realizations
    const auto max_rms = reportUnits(asArray(s.err_max_rms));
    const auto overall = reportUnits(asArray(s.evaluation.overall_rms));
    const auto diff = s.label == "REAL" ? std::nullopt : report.diff(s.label);
    for (std::size_t i = 0; i < names.size(); ++i) {
      BatchStatisticRow row{s.label, names[i], err[i], max_rms[i], overall[i], std::nullopt};
      if (diff && std::isfinite(asArray(*diff)[i])) row.diff = asArray(*diff)[i];
      rec.statistics.push_back(row);
    }
    for (std::size_t k = 0; k < s.evaluation.outages.size(); ++k) {
      const auto& o = s.evaluation.outages[k];
      const auto m = reportUnits(asArray(o.max));
      rec.outages.push_back({s.label, static_cast<int>(k), o.window.start_s, o.window.end_s,
                             o.epochs, m[0], m[1], m[2], m[3], m[4]});
    }
  }
  return rec;
}

// Temporary files a killed run of this task left in its folder (hidden ".<name>.tmp.*", the
// atomic writers' pattern). The folder belongs to this task only, so they are the task's own.
void removeStaleTemporaries(const BatchTask& t) {
  if (!fs::is_directory(t.out_dir)) return;
  for (const auto& e : fs::directory_iterator(t.out_dir)) {
    const std::string n = e.path().filename().string();
    if (n.size() > 1 && n[0] == '.' && n.find(".tmp.") != std::string::npos) fs::remove(e.path());
  }
}

// Runs one task in-process and records it (ok or failed) in its task database.
BatchRunRecord runTask(const BatchManifest& m, const BatchTask& t) {
  BatchRunRecord rec;
  const auto t0 = std::chrono::steady_clock::now();
  removeStaleTemporaries(t);
  std::string log_text;
  try {
    SgEvaluateOptions o;
    o.case_dir = t.case_dir;
    o.out_dir = t.out_dir;
    o.estimator = t.estimator;
    o.config_path = m.config;
    o.seed = t.seed;
    o.plots = m.plots;
    o.write_grafted_imu = false;
    o.jobs = 1;
    if (t.schedule) {
      o.outage_length_s = t.schedule->length_s;
      o.outage_period_s = t.schedule->period_s;
      o.outage_start_s = t.schedule->start_s;
    }
    fs::create_directories(t.out_dir);
    rec = recordOf(runSgEvaluation(o, [&](const std::string& s) { log_text += s + "\n"; }));
    const BatchPredictive p = readPredictive((fs::path(t.out_dir) / "evaluation.json").string());
    rec.realizations = p.realizations;
    rec.predictive = p.rows;
  } catch (const std::exception& e) {
    rec = BatchRunRecord{};
    rec.error = e.what();
    log_text += std::string("error: ") + e.what() + "\n";
  }
  rec.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  fs::create_directories(t.out_dir);
  // The task's log, written once through the atomic writer like every other result.
  writeFileAtomically((fs::path(t.out_dir) / "log.txt").string(), log_text);
  writeTaskDatabase(taskDatabasePath(t), t, rec);
  return rec;
}

struct RunCounts {
  int ran = 0, skipped = 0, failed = 0;
};

// Runs tasks[first, last) on `jobs` threads, skipping those already finished with their id
// unless force. A failed task is recorded and the others go on.
RunCounts runTasks(const BatchManifest& m, const std::vector<BatchTask>& tasks, std::size_t first,
                   std::size_t last, int jobs, bool force) {
  std::vector<const BatchTask*> todo;
  RunCounts n;
  for (std::size_t i = first; i < last; ++i) {
    if (!force && taskDatabaseStatus(taskDatabasePath(tasks[i]), tasks[i].id) == TaskStatus::kOk) {
      ++n.skipped;
    } else {
      todo.push_back(&tasks[i]);
    }
  }
  const int threads = workerCount(todo.size(), jobs);
  fmt::print(stderr, "batch: tasks {}..{} of {}: {} finished before, {} to run on {} threads\n",
             first, last - 1, tasks.size(), n.skipped, todo.size(), threads);
  std::vector<std::string> errors(todo.size());
  const auto t0 = std::chrono::steady_clock::now();
  auto run = [&](std::size_t i) {
    try {
      const BatchRunRecord r = runTask(m, *todo[i]);
      if (!r.ok) errors[i] = r.error;
    } catch (const std::exception& e) {  // the record itself could not be written
      errors[i] = std::string("no record written: ") + e.what();
    }
  };
  auto report = [&](std::size_t i, std::size_t done) {
    const BatchTask& t = *todo[i];
    if (!errors[i].empty()) ++n.failed;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print(stderr, "[{}/{}] {:.0f} s  task {} {} {}: {}\n", done, todo.size(), el, t.index,
               t.id, t.name, errors[i].empty() ? "ok" : "FAILED (" + errors[i] + ")");
  };
  parallelFor(todo.size(), threads, run, report);
  n.ran = static_cast<int>(todo.size());
  return n;
}
// Merges the task databases into <out>/results.sqlite and writes the summaries from it.
CollectCounts collectAndSummarize(const BatchManifest& m, const std::vector<BatchTask>& tasks) {
  fs::create_directories(m.out_dir);
  const std::string db = (fs::path(m.out_dir) / "results.sqlite").string();
  const CollectCounts c = collectTaskDatabases(db, tasks);
  writeBatchSummaries(m.out_dir, readSummaryRows(db));
  fmt::print(
      "batch: {} tasks, {} ok, {} failed, {} missing; results: {}, summary: {}/summary.md and "
      "summary.csv\n",
      tasks.size(), c.ok, c.failed, c.missing, db, m.out_dir);
  return c;
}

void throwIfIncomplete(const CollectCounts& c, std::size_t total) {
  if (c.failed + c.missing > 0) {
    throw std::runtime_error(
        fmt::format("{} of {} batch tasks failed and {} have no record (see the summary)", c.failed,
                    total, c.missing));
  }
}

void listTasks(const std::vector<BatchTask>& tasks) {
  fmt::print("index\tid\tstatus\tname\n");
  for (const auto& t : tasks) {
    const auto s = taskDatabaseStatus(taskDatabasePath(t), t.id);
    const char* word = s == TaskStatus::kOk       ? "done"
                       : s == TaskStatus::kFailed ? "failed"
                                                  : "pending";
    fmt::print("{}\t{}\t{}\t{}\n", t.index, t.id, word, t.name);
  }
}

void writeSlurm(const BatchCli& cli, const BatchManifest& m, const std::vector<BatchTask>& tasks) {
  const SlurmScripts s =
      writeSlurmScripts(m.out_dir, fs::read_symlink("/proc/self/exe").string(), cli.manifest,
                        static_cast<int>(tasks.size()), cli.slurm_options);
  fmt::print(
      "batch: {} tasks in {} array elements of {}; scripts: {} and {}; submit with: bash {}\n",
      tasks.size(), s.array_size, cli.slurm_options.chunk, s.array_script, s.collect_script,
      shellQuote(s.submit_script));
  if (!cli.submit) return;
  const auto [array_id, collect_id] = submitSlurmScripts(s);
  fmt::print("batch: submitted array job {} and collect job {} (after the array); results in {}\n",
             array_id, collect_id, m.out_dir);
}

// Runs array element cli.task: tasks [task * chunk, (task + 1) * chunk), only those hashed.
void runElement(const BatchCli& cli, const BatchManifest& m, int jobs) {
  cli.slurm_options.validate();
  const std::size_t first = static_cast<std::size_t>(cli.task) * cli.slurm_options.chunk;
  const std::size_t last = first + cli.slurm_options.chunk;
  const std::vector<BatchTask> tasks = expandBatchTasks(m, first, last);
  if (first >= tasks.size()) {
    throw std::invalid_argument(
        fmt::format("--task {} with --chunk {}: the manifest has only {} tasks", cli.task,
                    cli.slurm_options.chunk, tasks.size()));
  }
  const RunCounts n = runTasks(m, tasks, first, std::min(tasks.size(), last), jobs, cli.force);
  fmt::print("batch: element {}: {} ran, {} skipped (finished before), {} failed\n", cli.task,
             n.ran, n.skipped, n.failed);
  if (n.failed > 0)
    throw std::runtime_error(fmt::format("{} task(s) of element {} failed", n.failed, cli.task));
}

void runBatch(const BatchCli& cli) {
  BatchManifest m = loadBatchManifest(cli.manifest);
  if (!cli.out.empty()) m.out_dir = cli.out;
  const int jobs = cli.jobs >= 0 ? cli.jobs : m.jobs;
  if (cli.task >= 0) return runElement(cli, m, jobs);
  if (cli.slurm) return writeSlurm(cli, m, expandBatchTasks(m, 0, 0));  // the count is enough
  const std::vector<BatchTask> tasks = expandBatchTasks(m);
  if (cli.list) return listTasks(tasks);
  if (cli.collect) return throwIfIncomplete(collectAndSummarize(m, tasks), tasks.size());
  const RunCounts n = runTasks(m, tasks, 0, tasks.size(), jobs, cli.force);
  fmt::print("batch: {} ran, {} skipped (finished before), {} failed\n", n.ran, n.skipped,
             n.failed);
  throwIfIncomplete(collectAndSummarize(m, tasks), tasks.size());
}

}  // namespace

void registerBatch(CLI::App& app) {
  auto cli = std::make_shared<BatchCli>();
  CLI::App* cmd = app.add_subcommand("batch",
                                     "Run the tasks of a manifest (cases x estimators x outage "
                                     "schedules x seeds) locally or on Slurm; "
                                     "resumable; results in SQLite and summary tables");
  cmd->add_option("manifest", cli->manifest, "batch manifest YAML")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--jobs", cli->jobs, "tasks in parallel (overrides the manifest; 0 = all cores)");
  cmd->add_option("--out", cli->out, "output folder (overrides the manifest's 'out')");
  cmd->add_flag("--force", cli->force, "rerun tasks that finished before");
  auto* list =
      cmd->add_flag("--list", cli->list, "print the tasks (index, id, status, name) and exit");
  auto* task = cmd->add_option("--task", cli->task,
                               "run array element I only (tasks I*chunk .. I*chunk+chunk-1)")
                   ->check(CLI::NonNegativeNumber);
  cmd->add_option("--chunk", cli->slurm_options.chunk, "tasks per array element (default 1)")
      ->check(CLI::PositiveNumber);
  auto* collect = cmd->add_flag("--collect", cli->collect,
                                "merge the task results into results.sqlite and summaries");
  auto* slurm =
      cmd->add_flag("--slurm", cli->slurm, "write an sbatch array script and a collect job script");
  auto* submit = cmd->add_flag("--submit", cli->submit,
                               "with --slurm: submit both (the collect job after the array)");
  cmd->add_option("--partition", cli->slurm_options.partition, "with --slurm: partition");
  cmd->add_option("--time", cli->slurm_options.time, "with --slurm: time limit per array element");
  cmd->add_option("--mem", cli->slurm_options.mem,
                  "with --slurm: memory per array element (e.g. 4G)");
  cmd->add_option("--cpus", cli->slurm_options.cpus,
                  "with --slurm: cpus per array element (default 1)")
      ->check(CLI::PositiveNumber);
  submit->needs(slurm);
  list->excludes(task, collect, slurm);
  task->excludes(collect, slurm);
  collect->excludes(slurm);
  cmd->callback([cli]() { runBatch(*cli); });
}

}  // namespace graftnav::app
