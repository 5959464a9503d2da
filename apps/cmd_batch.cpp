// graftnav batch MANIFEST.yaml: the manifest's task groups (every analysis command over cases x
// estimators x option values x outage schedules x seeds), run locally or as Slurm arrays,
// resumable, results in SQLite, summaries and fleet reports written from it (core/batch,
// docs/batch.md).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <map>
#include <memory>

#include "commands.h"
#include "graftnav/batch/batch_run.h"
#include "graftnav/batch/slurm.h"
#include "script_locator.h"

namespace graftnav::app {
namespace {
namespace fs = std::filesystem;

struct BatchCli {
  std::string manifest, out, command;
  int jobs = -1;
  bool list = false, force = false, collect = false, report = false, slurm = false, submit = false;
  int task = -1;
  SlurmOptions slurm_options;
};

std::string selfExe() { return fs::read_symlink("/proc/self/exe").string(); }
void log(const std::string& line) { fmt::print(stderr, "{}\n", line); }

std::vector<std::size_t> indicesOf(const std::vector<BatchTask>& tasks, const std::string& cmd) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < tasks.size(); ++i)
    if (cmd.empty() || cmd == batchCommandName(tasks[i].command)) out.push_back(i);
  return out;
}

void plotReports(const std::string& out_dir) {
  const std::string w = runPythonScript("plot_batch.py", {out_dir});
  if (!w.empty()) fmt::print(stderr, "warning: {}\n", w);
}

// Collects, writes the summaries and reports, and fails when a task failed or has no record.
void collectAndReport(const BatchManifest& m, const std::vector<BatchTask>& tasks) {
  const CollectCounts c = collectBatch(m, tasks);
  plotReports(m.out_dir);
  fmt::print(
      "batch: {} tasks, {} ok, {} failed, {} missing; results: {}/results.sqlite, summary: "
      "summary.md and summary.csv, fleet report: report.md\n",
      tasks.size(), c.ok, c.failed, c.missing, m.out_dir);
  if (c.failed + c.missing > 0)
    throw std::runtime_error(
        fmt::format("{} of {} batch tasks failed and {} have no record (see {}/report.md)",
                    c.failed, tasks.size(), c.missing, m.out_dir));
}

void listTasks(const std::vector<BatchTask>& tasks) {
  fmt::print("index\tid\tstatus\tcommand\tfolder\n");
  for (const auto& t : tasks) {
    const auto s = taskDatabaseStatus(taskDatabasePath(t), t.id);
    const char* word = s == TaskStatus::kOk       ? "done"
                       : s == TaskStatus::kFailed ? "failed"
                                                  : "pending";
    fmt::print("{}\t{}\t{}\t{}\t{}\n", t.index, t.id, word, batchCommandName(t.command),
               t.folder());
  }
}

// One array per command, its --mem from the largest finished task of that command.
void writeSlurm(const BatchCli& cli, const BatchManifest& m, const std::vector<BatchTask>& tasks) {
  std::map<std::string, SlurmArraySpec> specs;
  std::map<std::string, std::optional<double>> largest;
  std::vector<std::string> order;
  for (const auto& t : tasks) {
    const std::string c = batchCommandName(t.command);
    if (!specs.count(c)) order.push_back(c);
    specs[c].command = c;
    ++specs[c].task_count;
    const auto rss = taskPeakRssMb(taskDatabasePath(t));
    if (rss && !(largest[c] >= *rss)) largest[c] = rss;
  }
  std::vector<SlurmArraySpec> arrays;
  for (const auto& c : order) {
    const auto mb = proposedMemMb(largest[c], cli.slurm_options.cpus);
    if (mb) specs[c].mem = fmt::format("{}M", *mb);
    fmt::print("batch: {} {} tasks: --mem {}\n", specs[c].task_count, c,
               !cli.slurm_options.mem.empty() ? cli.slurm_options.mem + " (given)"
               : mb ? fmt::format("{}M proposed (largest finished {} task: {:.0f} MB peak RSS, "
                                  "x1.5, x{} per element)",
                                  *mb, c, *largest[c], cli.slurm_options.cpus)
                    : std::string("not set (no finished task to measure: the cluster's default)"));
    arrays.push_back(specs[c]);
  }
  const SlurmScripts s =
      writeSlurmScripts(m.out_dir, selfExe(), cli.manifest, arrays, cli.slurm_options);
  fmt::print("batch: {} array script(s) and {} in {}; submit with: bash {}\n", s.arrays.size(),
             fs::path(s.collect_script).filename().string(), s.dir, shellQuote(s.submit_script));
  if (!cli.submit) return;
  const auto [array_ids, collect_id] = submitSlurmScripts(s);
  std::string ids;
  for (const auto& id : array_ids) ids += (ids.empty() ? "" : ", ") + id;
  fmt::print("batch: submitted array job{} {} and collect job {} (after {}); results in {}\n",
             array_ids.size() > 1 ? "s" : "", ids, collect_id, array_ids.size() > 1 ? "them" : "it",
             m.out_dir);
}

// Array element cli.task: tasks [task * chunk, (task + 1) * chunk) of --command (or of all),
// only those hashed.
void runElement(const BatchCli& cli, const BatchManifest& m, int jobs) {
  cli.slurm_options.validate();
  std::vector<BatchTask> tasks = expandBatchTaskList(m);
  const std::vector<std::size_t> mine = indicesOf(tasks, cli.command);
  const std::size_t first = static_cast<std::size_t>(cli.task) * cli.slurm_options.chunk;
  if (first >= mine.size())
    throw std::invalid_argument(fmt::format(
        "--task {} with --chunk {}: the manifest has only {} {}tasks", cli.task,
        cli.slurm_options.chunk, mine.size(), cli.command.empty() ? "" : cli.command + " "));
  const std::vector<std::size_t> which(
      mine.begin() + first, mine.begin() + std::min(mine.size(), first + cli.slurm_options.chunk));
  assignTaskIds(m, which, &tasks);
  const BatchRunCounts n = runBatchTasks(m, tasks, which, selfExe(), jobs, cli.force, log);
  fmt::print("batch: element {}: {} ran, {} skipped (finished before), {} failed\n", cli.task,
             n.ran, n.skipped, n.failed);
  if (n.failed > 0)
    throw std::runtime_error(fmt::format("{} task(s) of element {} failed", n.failed, cli.task));
}

void runBatch(const BatchCli& cli) {
  BatchManifest m = loadBatchManifest(cli.manifest);
  if (!cli.out.empty()) m.out_dir = fs::absolute(cli.out).lexically_normal().string();
  if (!cli.command.empty() && !parseBatchCommand(cli.command))
    throw std::invalid_argument("--command: unknown command '" + cli.command + "'");
  const int jobs = cli.jobs >= 0 ? cli.jobs : m.jobs;
  if (cli.report) {
    writeBatchReports(m.out_dir);
    plotReports(m.out_dir);
    return fmt::print("batch: summaries and fleet report written from {}/results.sqlite\n",
                      m.out_dir);
  }
  if (cli.task >= 0) return runElement(cli, m, jobs);
  if (cli.slurm) return writeSlurm(cli, m, expandBatchTaskList(m));
  const std::vector<BatchTask> tasks = expandBatchTasks(m);
  if (cli.list) return listTasks(tasks);
  if (cli.collect) return collectAndReport(m, tasks);
  const BatchRunCounts n =
      runBatchTasks(m, tasks, indicesOf(tasks, ""), selfExe(), jobs, cli.force, log);
  fmt::print("batch: {} ran, {} skipped (finished before), {} failed\n", n.ran, n.skipped,
             n.failed);
  collectAndReport(m, tasks);
}

}  // namespace

void registerBatch(CLI::App& app) {
  auto cli = std::make_shared<BatchCli>();
  CLI::App* cmd = app.add_subcommand(
      "batch",
      "Run a manifest's task groups (navigate, compare, real, real-sg, evaluate, diagnose over "
      "cases, estimators, options, schedules, seeds) locally or on Slurm; resumable; results in "
      "SQLite, summaries and fleet reports");
  cmd->add_option("manifest", cli->manifest, "batch manifest YAML")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--jobs", cli->jobs, "tasks in parallel (overrides the manifest; 0 = all cores)");
  cmd->add_option("--out", cli->out, "output folder (overrides the manifest's 'out')");
  cmd->add_flag("--force", cli->force, "rerun tasks that finished before");
  auto* list = cmd->add_flag("--list", cli->list, "print the tasks (index, id, status, folder)");
  auto* task = cmd->add_option("--task", cli->task,
                               "run array element I only (tasks I*chunk .. I*chunk+chunk-1)")
                   ->check(CLI::NonNegativeNumber);
  auto* command = cmd->add_option("--command", cli->command,
                                  "with --task: count the elements over this command's tasks");
  cmd->add_option("--chunk", cli->slurm_options.chunk, "tasks per array element (default 1)")
      ->check(CLI::PositiveNumber);
  auto* collect = cmd->add_flag("--collect", cli->collect,
                                "merge the task results into results.sqlite, summaries, report");
  auto* report = cmd->add_flag("--report", cli->report,
                               "write the summaries and fleet report again from results.sqlite");
  auto* slurm = cmd->add_flag("--slurm", cli->slurm,
                              "write an sbatch array per command and a collect job script");
  auto* submit = cmd->add_flag("--submit", cli->submit,
                               "with --slurm: submit them (the collect job after the arrays)");
  cmd->add_option("--partition", cli->slurm_options.partition, "with --slurm: partition");
  cmd->add_option("--time", cli->slurm_options.time, "with --slurm: time limit per array element");
  cmd->add_option("--mem", cli->slurm_options.mem,
                  "with --slurm: memory per array element (e.g. 4G; default: proposed from the "
                  "largest finished task of each command)");
  cmd->add_option("--cpus", cli->slurm_options.cpus, "with --slurm: cpus per element (default 1)")
      ->check(CLI::PositiveNumber);
  submit->needs(slurm);
  command->needs(task);
  list->excludes(task, collect, slurm, report);
  task->excludes(collect, slurm, report);
  collect->excludes(slurm, report);
  slurm->excludes(report);
  cmd->callback([cli]() { runBatch(*cli); });
}

}  // namespace graftnav::app
