// End-to-end tests of `graftnav evaluate` and `graftnav batch` on the bundled sample.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "test_support.h"

namespace graftnav {
namespace {
namespace fs = std::filesystem;

struct RunResult {
  int exit_code;
  std::string output;
};

RunResult run(const std::string& args) {
  const std::string log = test::makeTempDir("run_log") + "/out.txt";
  const std::string cmd = test::graftnavBinary() + " " + args + " > '" + log + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WEXITSTATUS(rc), ss.str()};
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::json::parse(f);
}

std::string sample(const std::string& grade) { return test::sourceDir() + "/data/sample_" + grade; }
std::string sampleConfig() { return test::sourceDir() + "/configs/evaluate_sample.yaml"; }

// A writable copy of a sample case (symlinks resolved), optionally without some files.
std::string copyCase(const std::string& src, const std::string& tag) {
  const std::string dst = test::makeTempDir(tag) + "/case";
  fs::copy(src, dst, fs::copy_options::recursive);
  return dst;
}

TEST(Evaluate, WritesTheContractShapeAndConsistentDiff) {
  const std::string out = test::makeTempDir("eval") + "/out";
  const RunResult r = run("evaluate " + sample("tactical") + " --out " + out + " --run-config " +
                          sampleConfig() + " --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = readJson(out + "/evaluation.json");
  EXPECT_EQ(j["case"], "sample_tactical");
  EXPECT_EQ(j["estimator"], "ekf");
  EXPECT_EQ(j["outages"]["count"], 8);  // configs/evaluate_sample.yaml in the 14.5-min sample
  EXPECT_DOUBLE_EQ(j["outages"]["length_s"].get<double>(), 60.0);
  const std::vector<std::string> keys{"horizontal_m", "vertical_m", "roll_deg", "pitch_deg",
                                      "heading_deg"};
  for (const std::string sol : {"SG1", "SG2", "REAL"}) {
    for (const auto& k : keys) {
      ASSERT_TRUE(j["err"][sol][k].is_number()) << sol << " " << k;
      EXPECT_GT(j["err"][sol][k].get<double>(), 0.0);
    }
  }
  // DIFF is exactly |ERR_x - ERR_REAL| / ERR_REAL of the numbers written next to it.
  for (const std::string sol : {"SG1", "SG2"}) {
    for (const auto& k : keys) {
      const double e = j["err"][sol][k], real = j["err"]["REAL"][k];
      EXPECT_NEAR(j["diff"][sol][k].get<double>(), std::abs(e - real) / real, 1e-12);
    }
  }
  for (const std::string f : {"tables.md", "evaluation.csv", "outage_drift.csv", "errors_SG1.csv",
                              "IMU_SG1.txt", "IMU_SG2.txt", "calibration.yaml"}) {
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  }
}

TEST(Evaluate, MakesBothPlotsWhenMatplotlibIsThere) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "Debian's python3-matplotlib is not installed: the plots are skipped by design";
  }
  const std::string out = test::makeTempDir("eval_plots") + "/out";
  const RunResult r =
      run("evaluate " + sample("mems") + " --out " + out + " --run-config " + sampleConfig());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out + "/outage_errors.png"));
  EXPECT_TRUE(fs::exists(out + "/diff.png"));
}

TEST(Evaluate, WithoutARealRecordingStillGivesSgErrors) {
  const std::string c = copyCase(sample("tactical"), "noreal");
  fs::remove(c + "/field/tested_imu.txt");
  const std::string out = c + "/../out";
  const RunResult r =
      run("evaluate " + c + " --out " + out + " --run-config " + sampleConfig() + " --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = readJson(out + "/evaluation.json");
  EXPECT_TRUE(j["err"].contains("SG1"));
  EXPECT_TRUE(j["err"].contains("SG2"));
  EXPECT_FALSE(j["err"].contains("REAL"));
  EXPECT_FALSE(j.contains("diff"));
}

TEST(Evaluate, MissingLabFileIsAClearError) {
  const std::string c = copyCase(sample("tactical"), "nolab");
  fs::remove(c + "/lab/six_position/y_down.txt");
  const RunResult r = run("evaluate " + c + " --out " + c + "/../out --no-plots");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("y_down"), std::string::npos) << r.output;
}

TEST(Evaluate, MismatchedRateIsAClearError) {
  const std::string c = copyCase(sample("tactical"), "rate");
  // case.yaml claims 200 Hz for a 50 Hz recording.
  std::ifstream in(c + "/case.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string y = ss.str();
  const auto pos = y.find("imu_rate_hz: 50");
  ASSERT_NE(pos, std::string::npos);
  y.replace(pos, 15, "imu_rate_hz: 200");
  std::ofstream(c + "/case.yaml") << y;
  const RunResult r = run("evaluate " + c + " --out " + c + "/../out --no-plots");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("ref_imu.txt"), std::string::npos) << r.output;
}

// A diagnose config's switch that is not true or false names the file, line, key and value.
TEST(Diagnose, BadConfigSwitchNamesFileLineKeyAndValue) {
  const std::string dir = test::makeTempDir("diag_bad_cfg");
  std::ofstream(dir + "/cfg.yaml") << "bin_s: 0.05\nrandom_walk_sandwich: maybe\n";
  const RunResult r =
      run("diagnose " + sample("mems") + " --out " + dir + "/out --options " + dir + "/cfg.yaml");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("cfg.yaml:2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'random_walk_sandwich'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'maybe'"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace graftnav
