#pragma once
// Helpers of the batch tests: manifests written to a temporary folder, the built binary run.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"

namespace graftnav::batch_test {

struct RunResult {
  int exit_code;
  std::string output;
};

// Runs `command` through the shell (stdout and stderr captured).
inline RunResult shell(const std::string& command) {
  const std::string log = test::makeTempDir("batch_log") + "/out.txt";
  const int rc = std::system((command + " > '" + log + "' 2>&1").c_str());
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WEXITSTATUS(rc), ss.str()};
}

inline RunResult graftnav(const std::string& args) {
  return shell(test::graftnavBinary() + " " + args);
}

inline std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline void writeFile(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

// The first column of the first row of `sql` on the results database at db_path (-1 if none).
inline long long queryInt(const std::string& db_path, const std::string& sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr), SQLITE_OK)
      << sqlite3_errmsg(db) << ": " << sql;
  long long v = -1;
  if (st && sqlite3_step(st) == SQLITE_ROW) v = sqlite3_column_int64(st, 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
  return v;
}

inline std::string sample(const std::string& grade) {
  return test::sourceDir() + "/data/sample_" + grade;
}

// One grafted realization per task: the batch tests check bookkeeping, not statistics.
inline std::string tinyRunConfig() {
  return test::sourceDir() + "/configs/batch/tiny_tasks_run.yaml";
}

}  // namespace graftnav::batch_test
