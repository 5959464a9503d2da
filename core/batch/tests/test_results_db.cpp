// The results database: many writers at once, collecting, a database of another schema version
// refused with its version, and the summaries and fleet reports written from it.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <thread>

#include "batch_test_util.h"
#include "graftnav/batch/fleet_report.h"
#include "graftnav/batch/results_db.h"
#include "graftnav/batch/summary.h"
#include "graftnav/batch/task_outputs.h"

namespace graftnav {
namespace {
namespace fs = std::filesystem;
using batch_test::queryInt;
using batch_test::readFile;

std::vector<BatchTask> syntheticTasks(const std::string& dir, int n) {
  std::vector<BatchTask> tasks(n);
  for (int i = 0; i < n; ++i) {
    BatchTask& t = tasks[i];
    t.index = i;
    t.id = "id" + std::to_string(i);
    t.grp = i % 2 ? "cmp" : "evaluate";
    t.command = i % 2 ? BatchCommand::kCompare : BatchCommand::kEvaluate;
    t.case_name = "case" + std::to_string(i / 2);
    t.case_dir = dir + "/cases/" + t.case_name;
    t.estimator = i % 2 ? "ekf+rts" : "ekf";
    t.schedule_label = "config";
    if (!(i % 2)) t.seed = static_cast<unsigned long long>(i);
    t.options_json = "{}";
    t.name = t.case_name + "_" + std::to_string(i);
    t.out_dir = dir + "/out/tasks/" + t.grp + "/" + t.name;
  }
  return tasks;
}

BatchRunRecord syntheticRecord(int i) {
  BatchRunRecord rec;
  rec.ok = i % 5 != 0;
  rec.error = rec.ok ? "" : "synthetic failure " + std::to_string(i);
  rec.outage_count = 2;
  rec.peak_rss_mb = 100.0 + i;
  rec.cpu_seconds = 1.5;
  rec.statistics.push_back({"ekf", "SG1", "outage", "horizontal_m", "rms", 1.0 + i, "m"});
  rec.statistics.push_back({"ekf", "SG1", "outage", "horizontal_m", "diff", 0.25, "frac"});
  rec.outages.push_back({"SG1", 0, 10.0, 70.0, 60, 1.0 + i, 0.1, 0.01, 0.01, 0.05});
  rec.outages.push_back({"SG1", 1, 100.0, 160.0, 60, 2.0 + i, 0.2, 0.02, 0.02, 0.06});
  rec.effects.push_back({"claimed", "scale", "gyro", "value[0]", 1e-3, 1e-4, ""});
  if (i % 2)  // the compare tasks
    rec.cross_checks.push_back(
        {"ekf", "rts", "filter-smoother", "horizontal_m", 0.5, 0.2, 1.1, 2.0 + (i % 7), 600});
  return rec;
}

TEST(BatchDatabase, ParallelWritersThenCollectKeepEveryRow) {
  const std::string dir = test::makeTempDir("batch_db_parallel");
  constexpr int kTasks = 64;
  const std::vector<BatchTask> tasks = syntheticTasks(dir, kTasks);
  std::vector<std::thread> writers;
  for (int w = 0; w < 8; ++w) {
    writers.emplace_back([&, w]() {
      for (int i = w; i < kTasks; i += 8) {
        fs::create_directories(tasks[i].out_dir);
        writeTaskDatabase(tasks[i].out_dir + "/task.sqlite", tasks[i], syntheticRecord(i));
      }
    });
  }
  for (auto& t : writers) t.join();
  fs::remove(tasks[7].out_dir + "/task.sqlite");  // one task never finished
  EXPECT_EQ(taskDatabaseStatus(tasks[5].out_dir + "/task.sqlite", "id5"), TaskStatus::kFailed);
  EXPECT_EQ(taskDatabaseStatus(tasks[6].out_dir + "/task.sqlite", "id6"), TaskStatus::kOk);
  EXPECT_EQ(taskDatabaseStatus(tasks[6].out_dir + "/task.sqlite", "id5"), TaskStatus::kMissing);
  EXPECT_EQ(*taskPeakRssMb(tasks[6].out_dir + "/task.sqlite"), 106.0);
  EXPECT_FALSE(taskPeakRssMb(tasks[5].out_dir + "/task.sqlite"));  // failed: no measure

  const std::string db = dir + "/out/results.sqlite";
  const auto n = collectTaskDatabases(db, tasks);
  EXPECT_EQ(n.missing, 1);
  EXPECT_EQ(n.failed, 13);  // 0, 5, ..., 60
  EXPECT_EQ(n.ok, kTasks - 14);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks"), kTasks);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM runs"), kTasks - 1);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM outages"), 2 * (kTasks - 1));
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM effects"), kTasks - 1);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM cross_checks"), kTasks / 2 - 1);
  EXPECT_EQ(queryInt(db,
                     "SELECT count(*) FROM statistics WHERE measure = 'diff' AND unit = "
                     "'frac' AND schedule = 'config'"),
            kTasks - 1);
  EXPECT_EQ(queryInt(db,
                     "SELECT CAST(sum(value) AS INTEGER) FROM statistics WHERE measure = "
                     "'rms'"),
            kTasks * (kTasks + 1) / 2 - (1 + 7));  // sum of 1 + i over every task but 7
  EXPECT_EQ(queryInt(db, "SELECT CAST(peak_rss_mb AS INTEGER) FROM tasks WHERE task_id = 'id9'"),
            109);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks WHERE peak_rss_mb IS NULL"), 1);
  EXPECT_EQ(queryInt(db, "SELECT count(*) FROM tasks WHERE seed IS NULL AND command = 'compare'"),
            kTasks / 2);
  EXPECT_EQ(queryInt(db, "SELECT value FROM meta WHERE key = 'schema_version'"), 2);

  const auto rows = readBatchResults(db);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(kTasks));
  EXPECT_EQ(rows[7].status, TaskStatus::kMissing);
  EXPECT_EQ(rows[5].status, TaskStatus::kFailed);
  EXPECT_EQ(rows[6].status, TaskStatus::kOk);
  EXPECT_EQ(rows[5].error, "synthetic failure 5");
  EXPECT_EQ(rows[9].cross_checks.size(), 1u);
  EXPECT_EQ(rows[9].effects, 1);
}

// A schema-1 database (written by the previous graftnav) is refused, naming its version.
TEST(BatchDatabase, ADatabaseOfSchemaOneIsRefusedNamingItsVersion) {
  const std::string dir = test::makeTempDir("batch_db_v1");
  const std::vector<BatchTask> tasks = syntheticTasks(dir, 2);
  fs::create_directories(tasks[0].out_dir);
  const std::string old = tasks[0].out_dir + "/task.sqlite";
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(old.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);"
                         "INSERT INTO meta VALUES ('schema_version', '1');"
                         "CREATE TABLE runs (task_id TEXT PRIMARY KEY, status TEXT);"
                         "INSERT INTO runs VALUES ('id0', 'ok');",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  EXPECT_EQ(taskDatabaseStatus(old, "id0"), TaskStatus::kMissing) << "a run reruns the task";
  try {
    collectTaskDatabases(dir + "/results.sqlite", tasks);
    FAIL() << "collected a schema-1 task database";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(old), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir + "/results.sqlite"));
  try {
    readBatchResults(old);  // what --report reads
    FAIL() << "read a schema-1 results database";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 1; this graftnav reads version 2"),
              std::string::npos)
        << e.what();
  }
}

TEST(BatchReports, SummariesAndReportsAreWrittenFromTheDatabaseAlone) {
  const std::string dir = test::makeTempDir("batch_reports");
  const std::vector<BatchTask> tasks = syntheticTasks(dir, 12);
  for (int i = 0; i < 12; ++i) {
    fs::create_directories(tasks[i].out_dir);
    writeTaskDatabase(tasks[i].out_dir + "/task.sqlite", tasks[i], syntheticRecord(i));
  }
  const std::string db = dir + "/results.sqlite";
  collectTaskDatabases(db, tasks);
  const auto rows = readBatchResults(db);
  const std::string a = dir + "/a", b = dir + "/b";
  fs::create_directories(a);
  fs::create_directories(b);
  writeBatchSummaries(a, rows);
  writeFleetReports(a, rows);
  writeBatchSummaries(b, readBatchResults(db));
  writeFleetReports(b, readBatchResults(db));
  for (const char* f : {"summary.md", "summary.csv", "report.md", "report_estimators.csv",
                        "report_options.csv", "report_crosscheck.csv", "report_failed.csv"}) {
    EXPECT_FALSE(readFile(a + "/" + f).empty()) << f;
    EXPECT_EQ(readFile(a + "/" + f), readFile(b + "/" + f)) << f;
  }
  const std::string report = readFile(a + "/report.md");
  // Compare tasks 1, 3, ..., 11 (cases 0..5) with max |d|/sigma 2 + (i % 7): 3, 5, 7, 2, 4, 6;
  // 3 is not beyond; task 5 failed and is listed among the failures, not the cross-check.
  EXPECT_NE(report.find("ekf - rts | filter-smoother"), std::string::npos) << report;
  EXPECT_NE(report.find("case1 (5.0 sigma), case4 (4.0 sigma), case5 (6.0 sigma)"),
            std::string::npos)
      << report;
  EXPECT_EQ(report.find("case0 ("), std::string::npos) << report;
  EXPECT_NE(report.find("synthetic failure 5"), std::string::npos) << report;
  const std::string est = readFile(a + "/report_estimators.csv");
  // Evaluate tasks 2, 4, 6, 8 ok (0 and 10 failed): 3, 5, 7, 9 m -> median 6, p25 4.5.
  EXPECT_NE(est.find(",outage,horizontal_m,rms,m,4,3.000000,4.500000,6.000000,7.500000,9.000000,"
                     "6.000000"),
            std::string::npos)
      << est;
  EXPECT_DOUBLE_EQ(quantileOfSorted({1.0, 2.0, 3.0, 4.0}, 0.5), 2.5);
}

TEST(BatchSummary, ExperimentNamesStripOnlyANumericSeedSuffix) {
  EXPECT_EQ(experimentName("drive_seed12"), "drive");
  EXPECT_EQ(experimentName("drive_seed"), "drive_seed");
  EXPECT_EQ(experimentName("drive_seed1x"), "drive_seed1x");
  EXPECT_EQ(experimentName("drive"), "drive");
  EXPECT_EQ(csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(csvField("say \"x\""), "\"say \"\"x\"\"\"");
  EXPECT_EQ(csvField("{\"k\":1,\"j\":2}"), "\"{\"\"k\"\":1,\"\"j\"\":2}\"");
  EXPECT_EQ(solutionLabel("SG#1"), "SG1");
  EXPECT_EQ(solutionLabel("IMU_SG2"), "SG2");
  EXPECT_EQ(solutionLabel("REAL"), "REAL");
}

}  // namespace
}  // namespace graftnav
