// End-to-end tests of `graftnav batch`: task ids and folders, resuming, the results database,
// the Slurm scripts (run here by bash, without Slurm; the real cluster is the CTest
// slurm_batch_localhost) and concurrent writers.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "batch_db.h"
#include "batch_slurm.h"
#include "batch_summary.h"
#include "batch_task.h"
#include "test_support.h"

namespace graftnav {
namespace {
namespace fs = std::filesystem;
using app::BatchTask;

struct RunResult {
  int exit_code;
  std::string output;
};

// Runs `command` through the shell (stdout and stderr captured).
RunResult shell(const std::string& command) {
  const std::string log = test::makeTempDir("batch_log") + "/out.txt";
  const int rc = std::system((command + " > '" + log + "' 2>&1").c_str());
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WEXITSTATUS(rc), ss.str()};
}

RunResult graftnav(const std::string& args) { return shell(test::graftnavBinary() + " " + args); }

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string sample(const std::string& grade) { return test::sourceDir() + "/data/sample_" + grade; }

// One grafted realization per task: these tests check the bookkeeping, not the statistics.
std::string sampleConfig() { return test::sourceDir() + "/configs/batch/tiny_tasks_run.yaml"; }

// A manifest: the cases, EKF, the config's outage schedule, the seeds.
void writeManifest(const std::string& path, const std::vector<std::string>& cases,
                   const std::string& seeds, const std::string& config = sampleConfig()) {
  std::ofstream m(path);
  m << "out: out\nconfig: " << config << "\ncases:\n";
  for (const auto& c : cases) m << "  - \"" << c << "\"\n";
  m << "estimators: [ekf]\nseeds: " << seeds << "\n";
}

// index -> (id, status) from `batch --list`.
std::map<int, std::pair<std::string, std::string>> listTasks(const std::string& manifest) {
  const RunResult r = graftnav("batch " + manifest + " --list");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::map<int, std::pair<std::string, std::string>> tasks;
  std::istringstream in(r.output);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream f(line);
    int index;
    std::string id, status;
    if (f >> index >> id >> status) tasks[index] = {id, status};
  }
  return tasks;
}

long long queryInt(const std::string& db_path, const std::string& sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK)
      << db_path;
  sqlite3_stmt* st = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr), SQLITE_OK)
      << sqlite3_errmsg(db) << ": " << sql;
  long long v = -1;
  if (st && sqlite3_step(st) == SQLITE_ROW) v = sqlite3_column_int64(st, 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
  return v;
}

TEST(BatchTasks, IdsAreStableAndFollowTheInputsThatDecideTheResult) {
  const std::string dir = test::makeTempDir("batch_ids");
  fs::copy(sample("tactical"), dir + "/caseA", fs::copy_options::recursive);
  fs::copy(sample("tactical"), dir + "/caseB", fs::copy_options::recursive);
  writeManifest(dir + "/m.yaml", {"caseA", "caseB"}, "[1, 2]");
  const auto first = listTasks(dir + "/m.yaml");
  ASSERT_EQ(first.size(), 4u);
  EXPECT_EQ(listTasks(dir + "/m.yaml"), first);  // stable
  std::set<std::string> ids;
  for (const auto& [i, t] : first) {
    ids.insert(t.first);
    EXPECT_EQ(t.second, "pending");
  }
  EXPECT_EQ(ids.size(), 4u)
      << "two identical folders under two names, two seeds: four distinct ids";

  // One byte more in caseB's case.yaml: only caseB's ids change.
  std::ofstream(dir + "/caseB/case.yaml", std::ios::app) << "\n";
  const auto edited = listTasks(dir + "/m.yaml");
  EXPECT_EQ(edited.at(0), first.at(0));
  EXPECT_EQ(edited.at(1), first.at(1));
  EXPECT_NE(edited.at(2).first, first.at(2).first);
  EXPECT_NE(edited.at(3).first, first.at(3).first);

  // The config's bytes count, not its path: a copy gives the same ids, an edited copy new ones.
  fs::copy_file(sampleConfig(), dir + "/cfg.yaml");
  writeManifest(dir + "/m2.yaml", {"caseA", "caseB"}, "[1, 2]", dir + "/cfg.yaml");
  EXPECT_EQ(listTasks(dir + "/m2.yaml"), edited);
  std::ofstream(dir + "/cfg.yaml", std::ios::app) << "# edited\n";
  const auto config_edited = listTasks(dir + "/m2.yaml");
  ASSERT_EQ(config_edited.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_NE(config_edited.at(i).first, edited.at(i).first) << i;
}

TEST(BatchTasks, DuplicateTaskNamesAreAnErrorAtLoad) {
  const std::string dir = test::makeTempDir("batch_dup");
  fs::create_directories(dir + "/a/good");
  fs::create_directories(dir + "/b/good");
  writeManifest(dir + "/same_name.yaml", {"a/good", "b/good"}, "[1]");
  RunResult r = graftnav("batch " + dir + "/same_name.yaml --list");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("same_name.yaml:5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'good' twice"), std::string::npos) << r.output;

  writeManifest(dir + "/slash.yaml", {"a/good", "a/good/"}, "[1]");
  r = graftnav("batch " + dir + "/slash.yaml --list");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("'good' twice"), std::string::npos) << r.output;

  writeManifest(dir + "/seeds.yaml", {"a/good"}, "[3, 3]");
  r = graftnav("batch " + dir + "/seeds.yaml --list");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("'seeds' lists '3' twice"), std::string::npos) << r.output;

  // A trailing '/' alone is fine: the case is still named `good`.
  writeManifest(dir + "/ok.yaml", {"a/good/", "b/other"}, "[1]");
  fs::create_directories(dir + "/b/other");
  r = graftnav("batch " + dir + "/ok.yaml --list");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("good__ekf__config__seed1"), std::string::npos) << r.output;
}

TEST(BatchRuns, FinishedTasksAreSkippedForceRerunsAndTheSummaryIsTheSame) {
  const std::string dir = test::makeTempDir("batch_resume");
  writeManifest(dir + "/m.yaml", {sample("tactical")}, "[1, 2]");
  RunResult r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("batch: 2 ran, 0 skipped"), std::string::npos) << r.output;
  const std::string summary = readFile(dir + "/out/summary.csv");
  const std::string task_db = dir + "/out/tasks/sample_tactical__ekf__config__seed1/task.sqlite";
  const std::string record = readFile(task_db);
  ASSERT_FALSE(record.empty());
  for (const auto& [i, t] : listTasks(dir + "/m.yaml")) EXPECT_EQ(t.second, "done") << i;

  // Losing one task's record reruns that task only.
  fs::remove(dir + "/out/tasks/sample_tactical__ekf__config__seed2/task.sqlite");
  r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("batch: 1 ran, 1 skipped"), std::string::npos) << r.output;
  EXPECT_EQ(readFile(task_db), record) << "a finished task was run again";
  EXPECT_EQ(readFile(dir + "/out/summary.csv"), summary);

  r = graftnav("batch " + dir + "/m.yaml --jobs 2 --force");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("batch: 2 ran, 0 skipped"), std::string::npos) << r.output;
  EXPECT_EQ(readFile(dir + "/out/summary.csv"), summary);
}

TEST(BatchRuns, AFailedTaskLeavesItsMessageInTheDatabase) {
  const std::string dir = test::makeTempDir("batch_fail");
  writeManifest(dir + "/m.yaml", {sample("tactical"), dir + "/no_such_case"}, "[1]");
  const RunResult r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  EXPECT_NE(r.exit_code, 0);
  const std::string db = dir + "/out/results.sqlite";
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM runs WHERE status = 'ok'"), 1);
  EXPECT_EQ(
      queryInt(db,
               "SELECT count(*) FROM runs WHERE status = 'failed' AND error LIKE '%no_such_case%'"),
      1);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks"), 2);
  // The good task's statistics and per-outage rows (configs/evaluate_sample.yaml: 8 outages x
  // SG1, SG2, REAL).
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM run_statistics"), 15);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM outages"), 24);
  EXPECT_EQ(
      queryInt(db,
               "SELECT count(*) FROM run_statistics WHERE solution = 'REAL' AND diff IS NOT NULL"),
      0);
  const std::string md = readFile(dir + "/out/summary.md");
  EXPECT_NE(md.find("failed: "), std::string::npos) << md;
}

TEST(BatchRuns, ArrayElementsInParallelProcessesThenCollectEqualALocalRun) {
  const std::string dir = test::makeTempDir("batch_elements");
  writeManifest(dir + "/m.yaml", {sample("tactical"), sample("mems")}, "[1, 2]");
  const std::string exe = test::graftnavBinary();
  // Two elements of two tasks each, as two concurrent processes writing into one output folder.
  const RunResult par =
      shell(exe + " batch " + dir + "/m.yaml --out " + dir + "/array --task 0 --chunk 2 & " + exe +
            " batch " + dir + "/m.yaml --out " + dir + "/array --task 1 --chunk 2 & wait");
  ASSERT_EQ(par.exit_code, 0) << par.output;
  RunResult r = graftnav("batch " + dir + "/m.yaml --out " + dir + "/array --collect");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = graftnav("batch " + dir + "/m.yaml --out " + dir + "/local --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const std::string f :
       {"summary.csv", "summary.md", "summary_monte_carlo.csv", "summary_monte_carlo.md"}) {
    const std::string local = readFile(dir + "/local/" + f);
    EXPECT_FALSE(local.empty()) << f;
    EXPECT_EQ(readFile(dir + "/array/" + f), local) << f;
  }
  EXPECT_EQ(
      queryInt(dir + "/array/results.sqlite", "SELECT count(*) FROM runs WHERE status = 'ok'"), 4);
  // An element past the end is an error, not a silent no-op.
  r = graftnav("batch " + dir + "/m.yaml --out " + dir + "/array --task 2 --chunk 2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("only 4 tasks"), std::string::npos) << r.output;
}

// A case folder and a manifest folder named to break out of shell quoting: the generated array
// and collect scripts, run by bash as Slurm would, run the task and nothing else.
TEST(BatchSlurm, HostilePathsInTheScriptsRunNothingTheyShouldNot) {
  const std::string dir = test::makeTempDir("batch_hostile");
  const std::string evil = "it's a $(touch PWNED_DIR) `touch PWNED_TICK`; touch PWNED_SEMI \"q\"";
  const std::string mdir = dir + "/" + evil;
  fs::create_directories(mdir);
  fs::create_directory_symlink(sample("tactical"), mdir + "/case " + evil);
  {
    std::ofstream m(mdir + "/m.yaml");
    m << "out: 'out $(touch PWNED_OUT)'\nconfig: " << sampleConfig() << "\n"
      << "cases: ['case it''s a $(touch PWNED_DIR) `touch PWNED_TICK`; touch PWNED_SEMI \"q\"']\n";
  }
  const std::string q = app::shellQuote(mdir + "/m.yaml");
  RunResult r = graftnav("batch " + q + " --slurm --chunk 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string slurm_dir = mdir + "/out $(touch PWNED_OUT)/slurm";
  ASSERT_TRUE(fs::exists(slurm_dir + "/array.sbatch")) << r.output;
  r = shell("cd " + app::shellQuote(slurm_dir) +
            " && SLURM_ARRAY_TASK_ID=0 bash array.sbatch && bash collect.sbatch");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = readFile(mdir + "/out $(touch PWNED_OUT)/summary.csv");
  EXPECT_NE(summary.find("case it's a $(touch PWNED_DIR)"), std::string::npos) << summary;
  EXPECT_NE(summary.find(",ok,"), std::string::npos) << summary;
  for (const auto& root : {fs::path(dir), fs::path(mdir), fs::path(slurm_dir)}) {
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      EXPECT_EQ(e.path().filename().string().rfind("PWNED", 0), std::string::npos)
          << "injected: " << e.path();
    }
  }
  // Options reach #SBATCH lines unquoted, so they must be plain Slurm words.
  r = graftnav("batch " + q + " --slurm --partition 'gpu; rm -rf x'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--partition"), std::string::npos) << r.output;
  r = graftnav("batch " + q + " --slurm --mem '4G$(id)'");
  EXPECT_NE(r.exit_code, 0);
}

TEST(BatchSlurm, ScriptsHoldTheArrayTheChunkAndTheDependency) {
  const std::string dir = test::makeTempDir("batch_scripts");
  app::SlurmOptions o;
  o.partition = "short";
  o.time = "00:20:00";
  o.mem = "2G";
  o.cpus = 2;
  o.chunk = 4;
  const auto s = app::writeSlurmScripts(dir + "/out", "/opt/graftnav", dir + "/m.yaml", 10, o);
  EXPECT_EQ(s.array_size, 3);  // 4 + 4 + 2 tasks
  const std::string array = readFile(s.array_script);
  for (const std::string line :
       {"#SBATCH --array=0-2\n", "#SBATCH --partition=short\n", "#SBATCH --time=00:20:00\n",
        "#SBATCH --mem=2G\n", "#SBATCH --cpus-per-task=2\n",
        "--task \"$SLURM_ARRAY_TASK_ID\" --chunk 4 --jobs 2\n"}) {
    EXPECT_NE(array.find(line), std::string::npos) << line << "\n" << array;
  }
  EXPECT_NE(readFile(s.collect_script).find("--collect"), std::string::npos);
  EXPECT_NE(readFile(s.submit_script).find("--dependency=afterany:\"$array_id\" collect.sbatch"),
            std::string::npos);
}

// Many writers at once: each task writes its own database file, collecting merges them all.
TEST(BatchDatabase, ParallelWritersThenCollectKeepEveryRowAndThePredictiveIntervals) {
  const std::string dir = test::makeTempDir("batch_db_parallel");
  constexpr int kTasks = 64;
  std::vector<BatchTask> tasks(kTasks);
  for (int i = 0; i < kTasks; ++i) {
    BatchTask& t = tasks[i];
    t.index = i;
    t.id = "id" + std::to_string(i);
    t.case_name = "case" + std::to_string(i);
    t.case_dir = dir + "/cases/" + t.case_name;
    t.estimator = "ekf";
    t.schedule_label = "config";
    t.seed = static_cast<unsigned long long>(i);
    t.name = t.case_name;
    t.out_dir = dir + "/out/tasks/" + t.name;
  }
  // Predictive grafting's evaluation.json block, as the batch reads it after a task.
  const std::string json = dir + "/evaluation.json";
  std::ofstream(json)
      << R"({"case": "x", "realizations": 20, "predictive": {"SG1": {"horizontal_m": {"p05": 0.5, "p50": 1.0,
      "p95": 2.0, "mean": 1.1, "sd": 0.4}, "vertical_m": {"p05": 0.1, "p95": 0.3}}},
      "real_percentile": {"SG1": {"horizontal_m": 63.0, "vertical_m": null}},
      "verdict": {"SG1": {"horizontal_m": "consistent", "vertical_m": null}}})";
  const auto predictive = app::readPredictive(json);
  ASSERT_EQ(predictive.rows.size(), 2u);
  EXPECT_EQ(predictive.realizations, 20);
  EXPECT_TRUE(app::readPredictive(dir + "/absent.json").rows.empty());
  EXPECT_FALSE(app::readPredictive(dir + "/absent.json").realizations);

  std::vector<std::thread> writers;
  for (int w = 0; w < 8; ++w) {
    writers.emplace_back([&, w]() {
      for (int i = w; i < kTasks; i += 8) {
        app::BatchRunRecord rec;
        rec.ok = i % 5 != 0;
        rec.error = rec.ok ? "" : "synthetic failure " + std::to_string(i);
        rec.outage_count = 2;
        rec.statistics.push_back({"SG1", "horizontal_m", 1.0 + i, 2.0, 0.5, 0.25});
        rec.outages.push_back({"SG1", 0, 10.0, 70.0, 60, 1.0 + i, 0.1, 0.01, 0.01, 0.05});
        rec.outages.push_back({"SG1", 1, 100.0, 160.0, 60, 2.0 + i, 0.2, 0.02, 0.02, 0.06});
        rec.realizations = predictive.realizations;
        rec.predictive = predictive.rows;
        fs::create_directories(tasks[i].out_dir);
        app::writeTaskDatabase(tasks[i].out_dir + "/task.sqlite", tasks[i], rec);
      }
    });
  }
  for (auto& t : writers) t.join();
  fs::remove(tasks[7].out_dir + "/task.sqlite");  // one task never finished

  const std::string db = dir + "/out/results.sqlite";
  const auto n = app::collectTaskDatabases(db, tasks);
  EXPECT_EQ(n.missing, 1);
  EXPECT_EQ(n.failed, 13);  // 0, 5, ..., 60
  EXPECT_EQ(n.ok, kTasks - 14);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks"), kTasks);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM runs"), kTasks - 1);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM outages"), 2 * (kTasks - 1));
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM predictive_intervals"), 2 * (kTasks - 1));
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM runs WHERE realizations = 20"), kTasks - 1);
  EXPECT_EQ(queryInt(db,
                     "SELECT count(*) FROM predictive_intervals WHERE statistic = 'vertical_m' AND "
                     "p50 IS NULL"),
            kTasks - 1);
  EXPECT_EQ(queryInt(db,
                     "SELECT count(*) FROM predictive_intervals WHERE verdict = 'consistent' AND "
                     "real_percentile = 63.0"),
            kTasks - 1);
  EXPECT_EQ(queryInt(db, "SELECT CAST(sum(outage_rms) AS INTEGER) FROM run_statistics"),
            kTasks * (kTasks + 1) / 2 - (1 + 7));  // sum of 1 + i over every task but 7
  const auto rows = app::readSummaryRows(db);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(kTasks));
  EXPECT_EQ(rows[7].status, app::TaskStatus::kMissing);
  EXPECT_EQ(rows[5].status, app::TaskStatus::kFailed);
  EXPECT_EQ(rows[6].status, app::TaskStatus::kOk);
  EXPECT_EQ(rows[5].error, "synthetic failure 5");
}

TEST(BatchSummary, ExperimentNamesStripOnlyANumericSeedSuffix) {
  EXPECT_EQ(app::experimentName("drive_seed12"), "drive");
  EXPECT_EQ(app::experimentName("drive_seed"), "drive_seed");
  EXPECT_EQ(app::experimentName("drive_seed1x"), "drive_seed1x");
  EXPECT_EQ(app::experimentName("drive"), "drive");
}

}  // namespace
}  // namespace graftnav
