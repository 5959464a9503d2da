// A run config with a time_range given to a command that does not apply it (evaluate, diagnose,
// real, real-sg) stops the command before it writes anything, with a message naming the key, the
// command and the run config file (requireTimeRangeUnset); the same run config without the key
// gets past that check.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

// configs/navigate.yaml with `extra` appended.
std::string runConfig(const std::string& dir, const std::string& name, const std::string& extra) {
  const std::string path = dir + "/" + name;
  std::ifstream base(test::sourceDir() + "/configs/navigate.yaml");
  std::ofstream out(path);
  out << base.rdbuf() << "\n" << extra;
  return path;
}

// The arguments after the command for a run on the bundled MEMS sample.
std::string argsOf(const std::string& command, const std::string& out,
                   const std::string& run_config) {
  std::string args = command + " " + test::sourceDir() + "/data/sample_mems --out " + out +
                     " --no-plots --run-config " + run_config;
  if (command == "real-sg")
    args += " --ref-profile " + test::sourceDir() +
            "/configs/imu/pos830_navigation.yaml --tested-profile " + test::sourceDir() +
            "/configs/imu/pos1100_mems.yaml";
  return args;
}

TEST(TimeRangeRefused, EveryCommandThatDoesNotApplyItStopsBeforeItsOutput) {
  const std::string dir = test::makeTempDir("time_range_refused");
  const std::string ranged =
      runConfig(dir, "ranged.yaml", "time_range:\n  start_s: 456400\n  end_s: 456600\n");
  for (const std::string command : {"evaluate", "diagnose", "real", "real-sg"}) {
    const std::string out = dir + "/" + command;
    const test::CommandOutput o = test::runGraftnav(argsOf(command, out, ranged));
    EXPECT_NE(o.exit_code, 0) << command << ":\n" << o.text;
    EXPECT_THAT(o.text, HasSubstr("error: time_range is not applied by graftnav " + command +
                                  ": the run config '" + ranged +
                                  "' sets time_range (start_s 456400, end_s 456600)"))
        << command;
    EXPECT_FALSE(fs::exists(out)) << command << " wrote " << out;
  }
}

// The same run config without the key runs.
TEST(TimeRangeRefused, ARunConfigWithoutTheKeyRuns) {
  const std::string dir = test::makeTempDir("time_range_absent");
  const std::string plain = runConfig(dir, "plain.yaml", "");
  const test::CommandOutput o =
      test::runGraftnav(argsOf("real", dir + "/real", plain) + " --estimator ekf");
  EXPECT_EQ(o.exit_code, 0) << o.text;
  EXPECT_THAT(o.text, Not(HasSubstr("is not applied by")));
  EXPECT_TRUE(fs::exists(dir + "/real/summary.json"));
}

}  // namespace
}  // namespace graftnav
