#pragma once
// Helpers of the batch tests: manifests written to a temporary folder, the built binary run.
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

inline std::string sample(const std::string& grade) {
  return test::sourceDir() + "/data/sample_" + grade;
}

// One grafted realization per task: the batch tests check bookkeeping, not statistics.
inline std::string tinyRunConfig() {
  return test::sourceDir() + "/configs/batch/tiny_tasks_run.yaml";
}

}  // namespace graftnav::batch_test
