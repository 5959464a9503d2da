// A run config with a time_range given to a command that does not apply it (evaluate, diagnose,
// real-sg, real with a latency study) stops the command before it writes anything, with a message
// naming the key, the command and the run config file (requireTimeRangeUnset); the same run
// config without the key gets past that check, and real without a latency study applies it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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
  struct Refusing {
    std::string command, flags, named;
  };
  const std::vector<Refusing> commands = {
      {"evaluate", "", "evaluate"},
      {"diagnose", "", "diagnose"},
      {"real-sg", "", "real-sg"},
      {"real", " --estimator ekf --latency-scan", "real --latency-scan/--latency-grid"},
      {"real", " --estimator ekf --latency-grid 0,0.1", "real --latency-scan/--latency-grid"}};
  for (const auto& [command, flags, named] : commands) {
    const std::string out = dir + "/" + command;
    const test::CommandOutput o = test::runGraftnav(argsOf(command, out, ranged) + flags);
    EXPECT_NE(o.exit_code, 0) << command << ":\n" << o.text;
    EXPECT_THAT(o.text, HasSubstr("error: time_range is not applied by graftnav " + named +
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

// real applies the range, and refuses --start/--end with a latency study.
TEST(TimeRangeRefused, RealAppliesItWithoutALatencyStudy) {
  const std::string dir = test::makeTempDir("time_range_real");
  const std::string ranged =
      runConfig(dir, "ranged.yaml", "time_range:\n  start_s: 456400\n  end_s: 456600\n");
  const test::CommandOutput o =
      test::runGraftnav(argsOf("real", dir + "/real", ranged) + " --estimator ekf");
  EXPECT_EQ(o.exit_code, 0) << o.text;
  EXPECT_THAT(o.text, HasSubstr("note: time range 456400.000 .. 456600.000: "));
  EXPECT_TRUE(fs::exists(dir + "/real/summary.json"));
  const std::string plain = runConfig(dir, "plain.yaml", "");
  const test::CommandOutput s = test::runGraftnav(argsOf("real", dir + "/scan", plain) +
                                                  " --estimator ekf --latency-scan --start 456400");
  EXPECT_NE(s.exit_code, 0) << s.text;
  EXPECT_THAT(s.text, HasSubstr("--start/--end are not applied by graftnav real --latency-scan"));
  EXPECT_FALSE(fs::exists(dir + "/scan"));
}

}  // namespace
}  // namespace graftnav
