// End-to-end tests of predictive grafting in `graftnav evaluate`: the JSON keys and their
// relations, a seeded run reproducing itself whatever the thread count, outage shifts, and option
// errors raised before any output is written.
#include <gtest/gtest.h>

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

struct CliRun {
  int exit_code;
  std::string output;
};

CliRun graftnav(const std::string& args) {
  const std::string log = test::makeTempDir("pred_log") + "/out.txt";
  const int rc =
      std::system((test::graftnavBinary() + " " + args + " > '" + log + "' 2>&1").c_str());
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WEXITSTATUS(rc), ss.str()};
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string evaluateArgs(const std::string& out, const std::string& extra) {
  return "evaluate " + test::sourceDir() + "/data/sample_tactical --out " + out + " --config " +
         test::sourceDir() + "/configs/evaluate_sample.yaml --no-plots " + extra;
}

const std::vector<std::string> kStats{"horizontal_m", "vertical_m", "roll_deg", "pitch_deg",
                                      "heading_deg"};

TEST(EvaluatePredictive, KeysAndTheirRelations) {
  const std::string out = test::makeTempDir("pred_keys") + "/out";
  const CliRun r = graftnav(evaluateArgs(out, "--realizations 6 --seed 3"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(slurp(out + "/evaluation.json"));
  EXPECT_EQ(j["realizations"], 6);
  EXPECT_EQ(j["outage_shifts"], 1);
  for (const std::string sg : {"SG1", "SG2"}) {
    for (const auto& s : kStats) {
      const auto& p = j["predictive"][sg][s];
      // err.SGx is the mean over realizations, and DIFF is computed from it.
      EXPECT_NEAR(p["mean"].get<double>(), j["err"][sg][s].get<double>(),
                  1e-12 * p["mean"].get<double>());
      const double real = j["err"]["REAL"][s], mean = p["mean"];
      EXPECT_NEAR(j["diff"][sg][s].get<double>(), std::abs(mean - real) / real, 1e-12);
      EXPECT_LE(p["p05"].get<double>(), p["p50"].get<double>());
      EXPECT_LE(p["p50"].get<double>(), p["p95"].get<double>());
      EXPECT_GE(p["sd"].get<double>(), 0.0);
      const double pct = j["real_percentile"][sg][s];
      EXPECT_GE(pct, 0.0);
      EXPECT_LE(pct, 1.0);
      const std::string v = j["verdict"][sg][s];
      const bool inside = real >= p["p05"].get<double>() && real <= p["p95"].get<double>();
      EXPECT_EQ(v, inside                          ? "consistent"
                   : real > p["p95"].get<double>() ? "optimistic"
                                                   : "pessimistic");
      EXPECT_LE(j["diff_interval"][sg][s][0].get<double>(),
                j["diff_interval"][sg][s][1].get<double>());
    }
  }
  const std::string tables = slurp(out + "/tables.md");
  EXPECT_NE(tables.find("REAL in SG#2"), std::string::npos) << tables;
  EXPECT_NE(tables.find("## Reading this result"), std::string::npos);
  EXPECT_NE(r.output.find("REAL@"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out + "/predictive.csv"));
}

TEST(EvaluatePredictive, ASeededRunReproducesItselfWhateverTheThreads) {
  const std::string base = test::makeTempDir("pred_repro");
  ASSERT_EQ(graftnav(evaluateArgs(base + "/a", "--realizations 4 --seed 11 --jobs 1")).exit_code,
            0);
  ASSERT_EQ(graftnav(evaluateArgs(base + "/b", "--realizations 4 --seed 11 --jobs 2")).exit_code,
            0);
  ASSERT_EQ(graftnav(evaluateArgs(base + "/c", "--realizations 4 --seed 12 --jobs 2")).exit_code,
            0);
  const std::string a = slurp(base + "/a/evaluation.json"), b = slurp(base + "/b/evaluation.json"),
                    c = slurp(base + "/c/evaluation.json");
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(slurp(base + "/a/IMU_SG2.txt"), slurp(base + "/b/IMU_SG2.txt"));
}

TEST(EvaluatePredictive, OutageShiftsRepeatTheScheduleForSgAndRealAlike) {
  const std::string base = test::makeTempDir("pred_shift");
  ASSERT_EQ(graftnav(evaluateArgs(base + "/one", "--realizations 3")).exit_code, 0);
  const CliRun r = graftnav(evaluateArgs(base + "/two", "--realizations 3 --outage-shifts 2"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto one = nlohmann::json::parse(slurp(base + "/one/evaluation.json"));
  const auto two = nlohmann::json::parse(slurp(base + "/two/evaluation.json"));
  EXPECT_EQ(two["outage_shifts"], 2);
  ASSERT_EQ(two["outage_shift_starts_s"].size(), 2u);
  // The sample's schedule starts at 60 s with a 100 s period: the second start is 50 s later.
  EXPECT_NEAR(
      two["outage_shift_starts_s"][1].get<double>() - two["outage_shift_starts_s"][0].get<double>(),
      50.0, 1e-9);
  EXPECT_NE(one["err"]["REAL"]["horizontal_m"], two["err"]["REAL"]["horizontal_m"]);
}

TEST(EvaluatePredictive, BadOptionsFailBeforeAnyOutput) {
  const std::string base = test::makeTempDir("pred_bad");
  for (const std::string extra : {"--realizations 0", "--outage-shifts 0", "--outage-length -5",
                                  "--outage-start 1000", "--estimator kalman"}) {
    const std::string out = base + "/out";
    const CliRun r = graftnav(evaluateArgs(out, extra));
    EXPECT_NE(r.exit_code, 0) << extra << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << extra << ": " << out << " was created";
  }
  const CliRun r = graftnav(evaluateArgs(base + "/late", "--outage-start 1000"));
  EXPECT_NE(r.output.find("no outage fits"), std::string::npos) << r.output;
  const CliRun unknown = graftnav(evaluateArgs(base + "/unknown", "--estimator kalman"));
  EXPECT_NE(unknown.output.find("--estimator: kalman not in {ekf,"), std::string::npos)
      << unknown.output;  // the flag is named, with the estimators it takes
}

}  // namespace
}  // namespace graftnav
