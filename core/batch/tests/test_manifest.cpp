// The manifest: groups of every command, the expansion order, task ids, and every class of bad
// manifest refused with its file and line before any task runs.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>

#include "batch_test_util.h"
#include "graftnav/batch/manifest.h"
#include "graftnav/batch/tasks.h"

namespace graftnav {
namespace {
namespace fs = std::filesystem;
using batch_test::sample;
using batch_test::tinyRunConfig;
using batch_test::writeFile;

// A folder with two case folders (copies of nothing: ids only read their bytes) and a manifest.
std::string setUp(const std::string& tag, const std::string& manifest) {
  const std::string dir = test::makeTempDir(tag);
  for (const char* c : {"drive_a", "drive_b", "other"}) {
    fs::create_directories(dir + "/cases/" + c);
    writeFile(dir + "/cases/" + c + "/case.yaml", std::string("name: ") + c + "\n");
  }
  fs::copy_file(tinyRunConfig(), dir + "/run.yaml");
  writeFile(dir + "/profile.yaml", "name: p\n");
  writeFile(dir + "/m.yaml", manifest);
  return dir;
}

const char* kGroups = R"(out: out
groups:
  - command: navigate
    cases: [cases/drive_*]
    estimators: [ekf, rts]
    run_config: run.yaml
    options:
      ekf.gate_probability: [0.99, 0.999]
  - command: evaluate
    cases: [cases/drive_a]
    seeds: [1, 2]
    outage_schedules:
      - {length_s: 30, period_s: 100, start_s: 60}
  - command: compare
    name: cmp
    cases: [cases/drive_b]
    estimators: [ekf, rts, fgo]
    flags: {profile: profile.yaml, lenient: true}
)";

std::vector<std::string> folders(const std::vector<BatchTask>& tasks) {
  std::vector<std::string> out;
  for (const auto& t : tasks) out.push_back(t.folder());
  return out;
}

TEST(BatchManifest, GroupsExpandInAFixedOrderWithStableIds) {
  const std::string dir = setUp("manifest_order", kGroups);
  const BatchManifest m = loadBatchManifest(dir + "/m.yaml");
  ASSERT_EQ(m.groups.size(), 3u);
  const auto tasks = expandBatchTasks(m);
  const std::vector<std::string> want{"navigate/drive_a__ekf__config__ekf.gate_probability=0.99",
                                      "navigate/drive_a__ekf__config__ekf.gate_probability=0.999",
                                      "navigate/drive_a__rts__config__ekf.gate_probability=0.99",
                                      "navigate/drive_a__rts__config__ekf.gate_probability=0.999",
                                      "navigate/drive_b__ekf__config__ekf.gate_probability=0.99",
                                      "navigate/drive_b__ekf__config__ekf.gate_probability=0.999",
                                      "navigate/drive_b__rts__config__ekf.gate_probability=0.99",
                                      "navigate/drive_b__rts__config__ekf.gate_probability=0.999",
                                      "evaluate/drive_a__ekf__30s-every-100s-from-60s__seed1",
                                      "evaluate/drive_a__ekf__30s-every-100s-from-60s__seed2",
                                      "cmp/drive_b__ekf+rts+fgo__config"};
  EXPECT_EQ(folders(tasks), want);
  std::set<std::string> ids;
  for (const auto& t : tasks) {
    EXPECT_EQ(t.id.size(), 16u);
    ids.insert(t.id);
    EXPECT_EQ(t.index, &t - &tasks[0]);
  }
  EXPECT_EQ(ids.size(), tasks.size());
  EXPECT_EQ(tasks[1].options_json, R"({"ekf.gate_probability":0.999})");
  EXPECT_EQ(tasks[10].estimators, (std::vector<std::string>{"ekf", "rts", "fgo"}));
  EXPECT_FALSE(tasks[0].seed);
  EXPECT_EQ(*tasks[9].seed, 2u);

  // Stable: the same manifest loaded again, and the same cases under another folder.
  EXPECT_EQ(expandBatchTasks(loadBatchManifest(dir + "/m.yaml"))[3].id, tasks[3].id);
  const std::string copy = test::makeTempDir("manifest_order_copy");
  fs::copy(dir, copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const auto moved = expandBatchTasks(loadBatchManifest(copy + "/m.yaml"));
  for (std::size_t i = 0; i < tasks.size(); ++i) EXPECT_EQ(moved[i].id, tasks[i].id) << i;

  // Hashing only some tasks gives them the same ids.
  std::vector<BatchTask> some = expandBatchTaskList(m);
  assignTaskIds(m, {2, 9}, &some);
  EXPECT_EQ(some[2].id, tasks[2].id);
  EXPECT_EQ(some[9].id, tasks[9].id);
  EXPECT_TRUE(some[3].id.empty());
}

TEST(BatchManifest, AnIdChangesWhenExactlyOneOptionValueChanges) {
  const std::string dir = setUp("manifest_one_value", kGroups);
  const auto before = expandBatchTasks(loadBatchManifest(dir + "/m.yaml"));
  std::string edited = kGroups;
  edited.replace(edited.find("[0.99, 0.999]"), 13, "[0.99, 0.995]");
  writeFile(dir + "/m.yaml", edited);
  const auto after = expandBatchTasks(loadBatchManifest(dir + "/m.yaml"));
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    const bool changed_value = i < 8 && i % 2 == 1;  // the 0.999 tasks of the navigate group
    if (changed_value)
      EXPECT_NE(after[i].id, before[i].id) << i;
    else
      EXPECT_EQ(after[i].id, before[i].id) << i;
  }
  // A profile's bytes count: editing it changes the compare task's id only.
  writeFile(dir + "/profile.yaml", "name: p2\n");
  const auto profile = expandBatchTasks(loadBatchManifest(dir + "/m.yaml"));
  for (std::size_t i = 0; i + 1 < after.size(); ++i) EXPECT_EQ(profile[i].id, after[i].id) << i;
  EXPECT_NE(profile.back().id, after.back().id);
}

TEST(BatchManifest, TheEarlierLayoutIsOneEvaluateGroup) {
  const std::string dir = setUp("manifest_legacy",
                                "out: out\nconfig: run.yaml\nseeds: [3, 4]\ncases: [cases/other]\n"
                                "estimators: [ekf, fgo]\n");
  const BatchManifest m = loadBatchManifest(dir + "/m.yaml");
  ASSERT_EQ(m.groups.size(), 1u);
  EXPECT_EQ(m.groups[0].command, BatchCommand::kEvaluate);
  const auto tasks = expandBatchTasks(m);
  ASSERT_EQ(tasks.size(), 4u);
  EXPECT_EQ(tasks[0].folder(), "evaluate/other__ekf__config__seed3");
  const auto argv = taskCommandLine(m, tasks[0], "/bin/graftnav");
  const std::vector<std::string> want{"/bin/graftnav",
                                      "evaluate",
                                      fs::absolute(dir + "/cases/other").lexically_normal(),
                                      "--out",
                                      tasks[0].out_dir,
                                      "--estimator",
                                      "ekf",
                                      "--run-config",
                                      fs::absolute(dir + "/run.yaml").lexically_normal(),
                                      "--seed",
                                      "3",
                                      "--jobs",
                                      "1",
                                      "--no-plots"};
  EXPECT_EQ(argv, want);
}

TEST(BatchManifest, OptionsAndSchedulesGoIntoTheTasksRunConfig) {
  const std::string dir = setUp("manifest_run_config", R"(out: out
groups:
  - command: real
    cases: [cases/other]
    run_config: run.yaml
    outage_schedules: [{length_s: 20, period_s: 50, start_s: 10}]
    options: {fgo.window_nodes: [5], gnss.checkpoint_fix_types: [[0, 4]]}
    flags: {imu: tested, latency-grid: [0, 0.2]}
)");
  const BatchManifest m = loadBatchManifest(dir + "/m.yaml");
  const auto tasks = expandBatchTasks(m);
  ASSERT_EQ(tasks.size(), 1u);
  writeTaskRunConfig(m, tasks[0]);
  const std::string rc = taskRunConfigPath(m, tasks[0]);
  EXPECT_EQ(rc, tasks[0].out_dir + "/run_config.yaml");
  const YAML::Node n = YAML::LoadFile(rc);
  EXPECT_EQ(n["fgo"]["window_nodes"].as<int>(), 5);
  EXPECT_EQ(n["gnss"]["checkpoint_fix_types"][1].as<int>(), 4);
  EXPECT_EQ(n["outages"]["length_s"].as<double>(), 20.0);
  EXPECT_EQ(n["outages"]["period_s"].as<double>(), 50.0);
  EXPECT_EQ(n["grafting"]["realizations"].as<int>(), 1);  // the group's own key kept
  const auto argv = taskCommandLine(m, tasks[0], "g");
  const std::string line = [&] {
    std::string s;
    for (const auto& a : argv) s += a + " ";
    return s;
  }();
  EXPECT_NE(line.find("--imu tested --latency-grid 0,0.2"), std::string::npos) << line;
  EXPECT_NE(line.find("--run-config " + rc), std::string::npos) << line;
  EXPECT_EQ(tasks[0].name,
            "other__ekf__20s-every-50s-from-10s__fgo.window_nodes=5__gnss."
            "checkpoint_fix_types=_0__4_");
}

// Loads the manifest and returns the error (empty when it loads and expands).
std::string errorOf(const std::string& dir, const std::string& manifest) {
  writeFile(dir + "/m.yaml", manifest);
  try {
    expandBatchTasks(loadBatchManifest(dir + "/m.yaml"));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void expectRefused(const std::string& error, const std::string& file_line,
                   const std::string& what) {
  EXPECT_NE(error.find(file_line), std::string::npos) << error;
  EXPECT_NE(error.find(what), std::string::npos) << error;
}

TEST(BatchManifest, EveryClassOfBadManifestIsRefusedWithFileAndLine) {
  const std::string dir = setUp("manifest_bad", "out: out\n");
  const std::string m = dir + "/m.yaml";
  const std::string head = "out: out\ngroups:\n";
  expectRefused(errorOf(dir, head + "  - command: navigat\n    cases: [cases/other]\n"), m + ":3",
                "unknown command 'navigat'");
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/other]\n"
                                    "    options: {ekff.gate_probability: [0.9]}\n"),
                m + ":5", "ekff");
  expectRefused(errorOf(dir, head + "  - command: compare\n    cases: [cases/other]\n"
                                    "    flags:\n      latency-scan: true\n"),
                m + ":6", "`compare` takes no flag 'latency-scan'");
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/drive_a]\n"
                                    "  - command: navigate\n    cases: [cases/nothing_*]\n"),
                m + ":6", "the glob");
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/drive_a]\n"
                                    "  - command: navigate\n    cases: [cases/drive_*]\n"),
                m + ":5", "and the group at line 3 would both write tasks/navigate/drive_a__ekf");
  // And the others: a flag file that is not there, seeds on a command without, a missing
  // required flag, an unknown group key, a run config required.
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/other]\n"
                                    "    flags: {profile: nothere.yaml}\n"),
                m + ":5", "not found");
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/other]\n"
                                    "    seeds: [1, 2]\n"),
                m + ":5", "takes no grafting seed");
  expectRefused(errorOf(dir, head + "  - command: real-sg\n    cases: [cases/other]\n"
                                    "    run_config: run.yaml\n"),
                m + ":3", "needs the flag 'ref-profile'");
  expectRefused(errorOf(dir, head + "  - command: real\n    cases: [cases/other]\n"), m + ":3",
                "needs a run config");
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/other]\n"
                                    "    estimator: [ekf]\n"),
                m + ":5", "unknown key 'estimator'");
  // Two values that name one folder, and a name repeated.
  expectRefused(errorOf(dir, head + "  - command: navigate\n    cases: [cases/other]\n"
                                    "    options: {ekf.gate_probability: [0.9, 0.9]}\n"),
                m + ":5", "lists '0.9' twice");
}

// The option values are judged by the run config's own parser (core/case) over the group's run
// config: an unknown key, a wrong type and a value out of range are refused at the value's line,
// a section's keys given as a map are accepted and merged into the task's run config.
TEST(BatchManifest, OptionValuesAreJudgedByTheRunConfigParser) {
  const std::string dir = setUp("manifest_option_values", "out: out\n");
  const std::string m = dir + "/m.yaml";
  const std::string head =
      "out: out\ngroups:\n  - command: navigate\n    cases: [cases/other]\n"
      "    run_config: run.yaml\n    options:\n";
  expectRefused(errorOf(dir, head + "      ekf.gate_probabilty: [0.99]\n"), m + ":7",
                "unknown run-config key 'ekf.gate_probabilty' (the keys of ekf: ");
  expectRefused(errorOf(dir, head + "      ekff.gate_probability: [0.99]\n"), m + ":7",
                "unknown run-config key 'ekff' (the sections: ");
  expectRefused(errorOf(dir, head + "      ekf.gate_probability:\n        - 0.99\n"
                                    "        - high\n"),
                m + ":9", "expected a number, got 'high'");
  expectRefused(errorOf(dir, head + "      fgo.window_nodes: [5, 7.5]\n"), m + ":7",
                "expected an integer, got '7.5'");
  expectRefused(errorOf(dir, head + "      fgo.robust_loss: [huber, tukey]\n"), m + ":7", "tukey");
  expectRefused(errorOf(dir, head + "      grafting.realizations: [0]\n"), m + ":7",
                "must be >= 1, got 0");
  expectRefused(errorOf(dir, head + "      outages.length_s: [[30]]\n"), m + ":7",
                "expected a number, got a list");
  // A section given as a map: the key inside is checked too, and a good one merges.
  expectRefused(errorOf(dir, head + "      outages: [{lenght_s: 30}]\n"), m + ":7",
                "unknown run-config key 'outages.lenght_s'");
  ASSERT_EQ(errorOf(dir, head + "      outages: [{length_s: 30}]\n"), "");
  const BatchManifest ok = loadBatchManifest(m);
  const auto tasks = expandBatchTasks(ok);
  ASSERT_EQ(tasks.size(), 1u);
  writeTaskRunConfig(ok, tasks[0]);
  const YAML::Node n = YAML::LoadFile(taskRunConfigPath(ok, tasks[0]));
  EXPECT_EQ(n["outages"]["length_s"].as<double>(), 30.0);
  EXPECT_EQ(n["outages"]["period_s"].as<double>(), 100.0);  // the group's run config's key kept
}

TEST(BatchManifest, ABadValueNamesFileLineAndKey) {
  const std::string path = test::makeTempDir("manifest_bad_value") + "/m.yaml";
  writeFile(path, "out: out\ncases: [a]\nestimators: [ekf]\nseeds: [1, -2]\n");
  try {
    loadBatchManifest(path);
    FAIL() << "a negative seed was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path + ":4:"), std::string::npos) << m;
    EXPECT_NE(m.find("'seeds'"), std::string::npos) << m;
    EXPECT_NE(m.find("'-2'"), std::string::npos) << m;
  }
}

// A run config or an options value that sets time_range is refused, before any task runs, for a
// command that does not apply it (requireTimeRangeUnset's text, the manifest's line); navigate
// and compare take it.
TEST(BatchManifest, ATimeRangeIsRefusedForTheCommandsThatDoNotApplyIt) {
  const std::string dir = setUp("manifest_time_range", "out: out\n");
  writeFile(dir + "/ranged.yaml", "time_range: {start_s: 456400, end_s: 456600}\n");
  const std::string m = dir + "/m.yaml";
  const std::string head = "out: out\ngroups:\n";
  for (const std::string cmd : {"evaluate", "diagnose"}) {
    expectRefused(errorOf(dir, head + "  - command: " + cmd +
                                   "\n    cases: [cases/other]\n    run_config: ranged.yaml\n"),
                  m + ":5",
                  "time_range is not applied by graftnav " + cmd + ": the run config '" + dir +
                      "/ranged.yaml' sets time_range (start_s 456400, end_s 456600)");
  }
  expectRefused(errorOf(dir, head + "  - command: evaluate\n    cases: [cases/other]\n"
                                    "    run_config: run.yaml\n"
                                    "    options: {time_range.start_s: [456400]}\n"),
                m + ":6",
                "time_range is not applied by graftnav evaluate: the run config '" + dir +
                    "/run.yaml with options.time_range.start_s' sets time_range (start_s 456400)");
  for (const std::string cmd : {"navigate", "compare"}) {
    EXPECT_EQ(errorOf(dir, head + "  - command: " + cmd +
                               "\n    cases: [cases/other]\n    run_config: ranged.yaml\n"
                               "    options: {time_range.end_s: [456500]}\n"),
              "")
        << cmd;
  }
}

}  // namespace
}  // namespace graftnav
