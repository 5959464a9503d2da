// End-to-end runs of `graftnav batch` (the built binary, its tasks as child processes): resuming,
// a failed task's message, array elements against a local run, every command kind's rows, and
// the Slurm scripts run by bash (the real cluster is the CTest slurm_batch_localhost).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "graftnav/batch/slurm.h"

namespace graftnav {
namespace {
namespace fs = std::filesystem;
using batch_test::graftnav;
using batch_test::queryInt;
using batch_test::readFile;
using batch_test::RunResult;
using batch_test::sample;
using batch_test::shell;
using batch_test::tinyRunConfig;
using batch_test::writeFile;

// A manifest of today's shape: the cases, EKF, the config's outage schedule, the seeds.
void writeEvaluateManifest(const std::string& path, const std::vector<std::string>& cases,
                           const std::string& seeds) {
  std::string m = "out: out\nconfig: " + tinyRunConfig() + "\ncases:\n";
  for (const auto& c : cases) m += "  - \"" + c + "\"\n";
  writeFile(path, m + "estimators: [ekf]\nseeds: " + seeds + "\n");
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

TEST(BatchRuns, FinishedTasksAreSkippedForceRerunsAndTheSummaryIsTheSame) {
  const std::string dir = test::makeTempDir("batch_resume");
  writeEvaluateManifest(dir + "/m.yaml", {sample("tactical")}, "[1, 2]");
  RunResult r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("batch: 2 ran, 0 skipped"), std::string::npos) << r.output;
  const std::string summary = readFile(dir + "/out/summary.csv");
  const std::string task = dir + "/out/tasks/evaluate/sample_tactical__ekf__config__seed1";
  const std::string record = readFile(task + "/task.sqlite");
  ASSERT_FALSE(record.empty());
  EXPECT_FALSE(fs::exists(task + "/IMU_SG1.txt")) << "a batch keeps tables, not grafted IMUs";
  for (const auto& [i, t] : listTasks(dir + "/m.yaml")) EXPECT_EQ(t.second, "done") << i;
  // The child's peak memory and CPU time are recorded.
  const std::string db = dir + "/out/results.sqlite";
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks WHERE peak_rss_mb > 5 AND seconds > 0"), 2);

  // Losing one task's record reruns that task only.
  fs::remove(dir + "/out/tasks/evaluate/sample_tactical__ekf__config__seed2/task.sqlite");
  r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("batch: 1 ran, 1 skipped"), std::string::npos) << r.output;
  EXPECT_EQ(readFile(task + "/task.sqlite"), record) << "a finished task was run again";
  EXPECT_EQ(readFile(dir + "/out/summary.csv"), summary);

  r = graftnav("batch " + dir + "/m.yaml --jobs 2 --force");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("batch: 2 ran, 0 skipped"), std::string::npos) << r.output;
  EXPECT_EQ(readFile(dir + "/out/summary.csv"), summary);
  // --report writes the same files again from the database alone.
  fs::remove(dir + "/out/summary.csv");
  r = graftnav("batch " + dir + "/m.yaml --report");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(readFile(dir + "/out/summary.csv"), summary);
}

TEST(BatchRuns, AFailedTaskLeavesItsMessageInTheDatabase) {
  const std::string dir = test::makeTempDir("batch_fail");
  writeEvaluateManifest(dir + "/m.yaml", {sample("tactical"), dir + "/no_such_case"}, "[1]");
  const RunResult r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  EXPECT_NE(r.exit_code, 0);
  const std::string db = dir + "/out/results.sqlite";
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM runs WHERE status = 'ok'"), 1);
  EXPECT_EQ(queryInt(db,
                     "SELECT count(*) FROM runs WHERE status = 'failed' AND error LIKE '%exit "
                     "code%' AND error LIKE '%no_such_case%' AND exit_code <> 0"),
            1);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks"), 2);
  // The good task's statistics (SG1, SG2, REAL x five statistics x outage RMS and RMS of maxima,
  // SG1 and SG2 x five DIFF) and per-outage rows (configs/evaluate_sample.yaml: 8 outages).
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM statistics"), 40);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM outages"), 24);
  EXPECT_EQ(queryInt(db,
                     "SELECT count(*) FROM statistics WHERE solution = 'REAL' AND measure = "
                     "'diff'"),
            0);
  EXPECT_NE(readFile(dir + "/out/summary.md").find("failed: "), std::string::npos);
  EXPECT_NE(readFile(dir + "/out/report.md").find("no_such_case"), std::string::npos);
}

TEST(BatchRuns, ArrayElementsInParallelProcessesThenCollectEqualALocalRun) {
  const std::string dir = test::makeTempDir("batch_elements");
  writeEvaluateManifest(dir + "/m.yaml", {sample("tactical"), sample("mems")}, "[1, 2]");
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
  for (const std::string f : {"summary.csv", "summary.md", "summary_monte_carlo.csv",
                              "summary_monte_carlo.md", "report.md", "report_estimators.csv"}) {
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

TEST(BatchRuns, BadManifestsFailBeforeAnyTaskRuns) {
  const std::string dir = test::makeTempDir("batch_bad");
  writeFile(dir + "/m1.yaml", "out: out\ncases: [a]\nestimator: [ekf]\n");
  RunResult r = graftnav("batch " + dir + "/m1.yaml");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("m1.yaml:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'estimator'"), std::string::npos) << r.output;
  writeFile(dir + "/m2.yaml", "out: out\ncases: [a]\njobs: many\n");
  r = graftnav("batch " + dir + "/m2.yaml");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("m2.yaml:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("jobs"), std::string::npos) << r.output;
  writeFile(dir + "/m3.yaml", "out: out\n");
  r = graftnav("batch " + dir + "/m3.yaml");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("cases"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/out")) << "a task ran";
}

// The same case under two seed names: the experiment's mean must equal the single run's value,
// and DIFF of the means the single run's DIFF.
TEST(BatchRuns, MonteCarloSummaryGroupsSeedsAndAveragesThem) {
  const std::string dir = test::makeTempDir("batch_mc");
  fs::create_directory_symlink(sample("tactical"), dir + "/exp_seed1");
  fs::create_directory_symlink(sample("tactical"), dir + "/exp_seed2");
  writeEvaluateManifest(dir + "/m.yaml", {"exp_seed1", "exp_seed2"}, "[1]");
  const RunResult r = graftnav("batch " + dir + "/m.yaml --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto single = nlohmann::json::parse(
      readFile(dir + "/out/tasks/evaluate/exp_seed1__ekf__config__seed1/evaluation.json"));
  std::istringstream f(readFile(dir + "/out/summary_monte_carlo.csv"));
  std::string line;
  std::getline(f, line);  // header
  int rows = 0;
  while (std::getline(f, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
    ASSERT_EQ(c.size(), 12u) << line;
    EXPECT_EQ(c[1], "exp");
    EXPECT_EQ(c[5], "2");
    if (c[6] == "ERR_SG2_mean") {
      EXPECT_NEAR(std::stod(c[7]), single["err"]["SG2"]["horizontal_m"].get<double>(), 1e-5);
      ++rows;
    }
    if (c[6] == "DIFF_2_of_means") {
      EXPECT_NEAR(std::stod(c[7]), single["diff"]["SG2"]["horizontal_m"].get<double>(), 1e-4);
      ++rows;
    }
  }
  EXPECT_EQ(rows, 2);
}

// One manifest with a group of every command: each writes its own rows (statistics and the
// tables of its kind). real-sg and diagnose run on a real recording (../shared), whose tested
// IMU has standstills and a mismatch the finder reports.
TEST(BatchRuns, EveryCommandKindWritesItsRows) {
  const std::string wid = test::sharedDir() + "/data/real/wid_car_trial07";
  GRAFTNAV_REQUIRE_SHARED_PATH(wid);
  const std::string dir = test::makeTempDir("batch_every_kind");
  const std::string src = test::sourceDir(), tac = sample("tactical"), tiny = tinyRunConfig();
  writeFile(dir + "/m.yaml",
            "out: out\njobs: 2\ngroups:\n"
            "  - {command: navigate, cases: [" +
                tac + "], run_config: " + tiny +
                "}\n"
                "  - {command: compare, cases: [" +
                tac + "], estimators: [ekf, rts], run_config: " + tiny +
                "}\n"
                "  - {command: real, cases: [" +
                tac + "], run_config: " + tiny +
                ", options: {gnss.checkpoint_fix_types: [[0]]}}\n"
                "  - {command: evaluate, cases: [" +
                tac + "], run_config: " + tiny +
                "}\n"
                "  - command: real-sg\n    cases: [" +
                wid +
                "]\n    estimators: [ekf]\n"
                "    run_config: " +
                src +
                "/configs/real/wid_car.yaml\n"
                "    flags: {ref-profile: " +
                src + "/configs/real/wid_mrup.yaml, tested-profile: " + src +
                "/configs/real/wid_dot.yaml, static-gyro-threshold: 0.02, "
                "static-accel-threshold: 0.65, realizations: 2}\n"
                "  - {command: diagnose, cases: [" +
                wid + "]}\n");
  const RunResult r = graftnav("batch " + dir + "/m.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string db = dir + "/out/results.sqlite";
  auto count = [&](const std::string& command, const std::string& table,
                   const std::string& where = "1") {
    return queryInt(db, "SELECT count(*) FROM " + table + " x JOIN tasks t USING (task_id) " +
                            "WHERE t.command = '" + command + "' AND " + where);
  };
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM runs WHERE status = 'ok'"), 6);
  // navigate: overall, outage and RMS of maxima of the five statistics, NEES; one row per outage.
  EXPECT_EQ(count("navigate", "statistics", "scope = 'outage' AND measure = 'rms'"), 5);
  EXPECT_EQ(count("navigate", "statistics", "scope = 'overall' AND statistic = 'nees'"), 1);
  EXPECT_EQ(count("navigate", "outages"), 8);
  // compare: both estimators' errors, the pair's differences.
  EXPECT_EQ(count("compare", "statistics",
                  "scope = 'outage' AND measure = 'rms' AND "
                  "statistic = 'horizontal_m'"),
            2);
  EXPECT_EQ(count("compare", "cross_checks", "a = 'ekf' AND b = 'rts'"), 3);
  // ekf and rts carry sigmas: the pair is weighed as a filter and its own smoother.
  EXPECT_EQ(count("compare", "cross_checks",
                  "sigma_form = 'filter-smoother' AND rms_normalized > 0 AND epochs > 0"),
            3);
  // real: the check points and the reference (the sample's truth).
  EXPECT_EQ(count("real", "statistics",
                  "scope = 'checkpoint' AND statistic = 'points' AND "
                  "value > 0"),
            1);
  EXPECT_EQ(count("real", "statistics", "scope = 'reference' AND statistic = 'horizontal_m'"), 2);
  // evaluate and real-sg: ERR and DIFF per grafted solution, REAL, predictive intervals.
  EXPECT_EQ(count("evaluate", "statistics", "measure = 'diff'"), 10);
  EXPECT_EQ(count("evaluate", "predictive_intervals"), 10);
  EXPECT_EQ(count("real-sg", "statistics", "solution = 'SG1' AND measure = 'diff'"), 5);
  EXPECT_EQ(count("real-sg", "statistics", "solution = 'REAL' AND measure = 'rms'"), 5);
  EXPECT_GT(count("real-sg", "outages"), 0);
  // diagnose: the finder's effects, one row per parameter.
  EXPECT_GT(count("diagnose", "effects", "kind = 'claimed' AND x.name = 'time_offset'"), 0);
  for (const char* f : {"summary.md", "report.md", "report_estimators.csv"})
    EXPECT_FALSE(readFile(dir + "/out/" + f).empty()) << f;
}

// A case folder and a manifest folder named to break out of shell quoting: the generated array
// and collect scripts, run by bash as Slurm would, run the task and nothing else.
TEST(BatchSlurm, HostilePathsInTheScriptsRunNothingTheyShouldNot) {
  const std::string dir = test::makeTempDir("batch_hostile");
  const std::string evil = "it's a $(touch PWNED_DIR) `touch PWNED_TICK`; touch PWNED_SEMI \"q\"";
  const std::string mdir = dir + "/" + evil;
  fs::create_directories(mdir);
  fs::create_directory_symlink(sample("tactical"), mdir + "/case " + evil);
  writeFile(mdir + "/m.yaml",
            "out: 'out $(touch PWNED_OUT)'\nconfig: " + tinyRunConfig() + "\n" +
                "cases: ['case it''s a $(touch PWNED_DIR) `touch PWNED_TICK`; touch PWNED_SEMI "
                "\"q\"']\n");
  const std::string q = shellQuote(mdir + "/m.yaml");
  RunResult r = graftnav("batch " + q + " --slurm --chunk 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string slurm_dir = mdir + "/out $(touch PWNED_OUT)/slurm";
  ASSERT_TRUE(fs::exists(slurm_dir + "/array_evaluate.sbatch")) << r.output;
  r = shell("cd " + shellQuote(slurm_dir) +
            " && SLURM_ARRAY_TASK_ID=0 bash array_evaluate.sbatch && bash collect.sbatch");
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
  // With the task finished, --slurm proposes --mem from its peak RSS.
  r = graftnav("batch " + q + " --slurm");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("M proposed (largest finished evaluate task"), std::string::npos)
      << r.output;
  EXPECT_NE(readFile(slurm_dir + "/array_evaluate.sbatch").find("#SBATCH --mem="),
            std::string::npos);
}

TEST(BatchSlurm, ScriptsHoldAnArrayPerCommandTheChunkAndTheDependency) {
  const std::string dir = test::makeTempDir("batch_scripts");
  SlurmOptions o;
  o.partition = "short";
  o.time = "00:20:00";
  o.cpus = 2;
  o.chunk = 4;
  const auto s = writeSlurmScripts(dir + "/out", "/opt/graftnav", dir + "/m.yaml",
                                   {{"real", 10, "512M"}, {"compare", 3, ""}}, o);
  ASSERT_EQ(s.arrays.size(), 2u);
  EXPECT_EQ(s.arrays[0].array_size, 3);  // 4 + 4 + 2 tasks
  EXPECT_EQ(s.arrays[1].array_size, 1);
  const std::string real = readFile(s.arrays[0].script);
  for (const std::string line :
       {"#SBATCH --array=0-2\n", "#SBATCH --partition=short\n", "#SBATCH --time=00:20:00\n",
        "#SBATCH --mem=512M\n", "#SBATCH --cpus-per-task=2\n",
        "--command real --task \"$SLURM_ARRAY_TASK_ID\" --chunk 4 --jobs 2\n"}) {
    EXPECT_NE(real.find(line), std::string::npos) << line << "\n" << real;
  }
  EXPECT_EQ(readFile(s.arrays[1].script).find("--mem"), std::string::npos);
  EXPECT_NE(readFile(s.collect_script).find("--collect"), std::string::npos);
  const std::string submit = readFile(s.submit_script);
  EXPECT_NE(submit.find("sbatch --parsable array_real.sbatch"), std::string::npos) << submit;
  EXPECT_NE(submit.find("--dependency=afterany\"$ids\" collect.sbatch"), std::string::npos);
  EXPECT_EQ(proposedMemMb(std::nullopt, 1), std::nullopt);
  EXPECT_EQ(*proposedMemMb(100.0, 1), 256);
  EXPECT_EQ(*proposedMemMb(300.0, 2), 960);  // 900 rounded up to 64 MiB
}

}  // namespace
}  // namespace graftnav
