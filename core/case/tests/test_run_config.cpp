// The run config from text, a node and dotted-key overrides: the values land in their structs,
// a key not given keeps the base's value, and every error names the source, line and key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "graftnav/case/run_config.h"
#include "graftnav/nav/units.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

using test::errorOf;

TEST(RunConfig, TextFillsEverySectionAndLeavesTheRestAtDefaults) {
  RunConfigReport report;
  const RunConfig c = parseRunConfigText(
      "outages: {length_s: 30, period_s: 120}\n"
      "ekf: {gate_probability: 0.99, alignment: static}\n"
      "fgo: {window_nodes: 7, robust_loss: cauchy}\n"
      "gnss: {fix_types: [4, 5], latency_s_by_fix_type: {4: 0.2}}\n"
      "grafting: {realizations: 5}\n"
      "time_range: {start_s: 100, end_s: 200}\n"
      "evaluation: {csv_rate_hz: 2}\n",
      "options", &report);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_TRUE(c.outages_given);
  EXPECT_EQ(c.outages.length_s, 30.0);
  EXPECT_EQ(c.outages.start_s, OutageScheduleConfig{}.start_s);
  EXPECT_EQ(c.ekf.gate_probability, 0.99);
  EXPECT_EQ(c.ekf.record_interval_s, EkfOptions{}.record_interval_s);
  EXPECT_EQ(c.alignment.mode, AlignmentMode::kStatic);
  EXPECT_EQ(c.fgo.window_nodes, 7);
  EXPECT_EQ(c.fgo.robust_loss, RobustLoss::kCauchy);
  EXPECT_TRUE(c.gnss.given);
  EXPECT_EQ(c.gnss.selection.accepted_fix_types, (std::vector<int>{4, 5}));
  EXPECT_EQ(c.gnss.selection.latency_s_by_fix_type.at(4), 0.2);
  EXPECT_EQ(c.grafting.realizations, 5);
  EXPECT_EQ(*c.time_range.end_s, 200.0);
  EXPECT_EQ(c.evaluation.csv_rate_hz, 2.0);
  // A run config is the estimators' options as they are.
  const EstimatorOptions& o = c;
  EXPECT_EQ(o.fgo.window_nodes, 7);
}

TEST(RunConfig, FileAndTextGiveTheSameConfig) {
  const std::string path = test::makeTempDir("run_config_file") + "/run.yaml";
  const std::string text = "ekf: {init_heading_std_deg: 2.5}\noutages: {start_s: 50}\n";
  std::ofstream(path) << text;
  const RunConfig a = loadRunConfig(path);
  const RunConfig b = parseRunConfigText(text, "options");
  EXPECT_EQ(a.ekf.init_heading_std_rad, b.ekf.init_heading_std_rad);
  EXPECT_NEAR(a.ekf.init_heading_std_rad, 2.5 * units::kDegToRad, 1e-15);
  EXPECT_EQ(a.outages.start_s, b.outages.start_s);
}

TEST(RunConfig, UnknownKeysAreReportedDottedAndWithTheirLine) {
  RunConfigReport report;
  parseRunConfigText("ekf:\n  gate_probabilty: 0.9\nodometr: {}\n", "run.yaml", &report);
  EXPECT_EQ(report.unknown_keys, (std::vector<std::string>{"odometr", "ekf.gate_probabilty"}));
  ASSERT_EQ(report.warnings.size(), 2u);
  EXPECT_THAT(report.warnings[1], HasSubstr("run.yaml:2: unknown key 'ekf.gate_probabilty'"));
}

TEST(RunConfig, ErrorsNameSourceLineAndKey) {
  EXPECT_THAT(errorOf([] { parseRunConfigText("ekf:\n  gate_probability: x\n", "a.yaml"); }),
              HasSubstr("a.yaml:2: key 'ekf.gate_probability': expected a number, got 'x'"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("ekf: {alignment: sideways}\n", "a.yaml"); }),
              HasSubstr("key 'ekf.alignment': 'sideways' is not one of given, static, motion"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("ekf: {covariance_interval_s: -1}\n", "a.yaml"); }),
              HasSubstr("a.yaml: section ekf: "));
  EXPECT_THAT(
      errorOf([] { parseRunConfigText("fgo:\n  robust_loss: tukey\n", "a.yaml"); }),
      HasSubstr("a.yaml:2: key 'fgo.robust_loss': 'tukey': expected huber, cauchy or none"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("ekf: [1, 2]\n", "a.yaml"); }),
              HasSubstr("key 'ekf': expected a map"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("ekf: {a: [1\n", "a.yaml"); }),
              HasSubstr("a.yaml:2: YAML syntax error"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("imupath: x.txt\n", "kf.yaml"); }),
              HasSubstr("graftnav import kf-gins|ob-gins kf.yaml"));
}

// The graphs' IMU scale-factor states: each spelling lands on its mode, the default stays when
// the key is absent, and a wrong word is named with its line and the accepted words.
TEST(RunConfig, FgoImuScaleStatesParseEachModeAndNameAWrongOne) {
  EXPECT_EQ(parseRunConfigText("fgo: {window_nodes: 5}\n", "a.yaml").fgo.imu_scale_states,
            ImuScaleStates::kWithVehicleAiding);
  EXPECT_EQ(parseRunConfigText("fgo: {imu_scale_states: off}\n", "a.yaml").fgo.imu_scale_states,
            ImuScaleStates::kOff);
  EXPECT_EQ(parseRunConfigText("fgo: {imu_scale_states: on}\n", "a.yaml").fgo.imu_scale_states,
            ImuScaleStates::kOn);
  EXPECT_EQ(parseRunConfigText("fgo: {imu_scale_states: with_vehicle_aiding}\n", "a.yaml")
                .fgo.imu_scale_states,
            ImuScaleStates::kWithVehicleAiding);
  EXPECT_THAT(errorOf([] { parseRunConfigText("fgo:\n  imu_scale_states: always\n", "a.yaml"); }),
              HasSubstr("a.yaml:2: key 'fgo.imu_scale_states': 'always': expected off, "
                        "with_vehicle_aiding or on"));
}

TEST(RunConfig, DottedOverridesChangeOnlyTheirKeyAndAreValidated) {
  RunConfig base = parseRunConfigText("ekf: {gate_probability: 0.9, init_pos_std_m: 2}\n", "base");
  RunConfigReport report;
  const RunConfig c = applyRunConfigOverrides(
      base,
      {{"ekf.gate_probability", "0.99"}, {"outages", "{length_s: 30}"}, {"gnss.fix_types", "[4]"}},
      "options", &report);
  EXPECT_EQ(c.ekf.gate_probability, 0.99);
  EXPECT_EQ(c.ekf.init_pos_std_m, 2.0);  // the base's, kept
  EXPECT_TRUE(c.outages_given);
  EXPECT_EQ(c.outages.length_s, 30.0);
  EXPECT_EQ(c.gnss.selection.accepted_fix_types, (std::vector<int>{4}));
  EXPECT_TRUE(report.unknown_keys.empty());
  EXPECT_EQ(base.ekf.gate_probability, 0.9);  // the base is not changed

  EXPECT_EQ(errorOf([&] {
              applyRunConfigOverrides(base, {{"ekf.gate_probability", "x"}}, "options");
            }),
            "options: key 'ekf.gate_probability': expected a number, got 'x'");
  EXPECT_THAT(errorOf([&] {
                applyRunConfigOverrides(base, {{"grafting.realizations", "0"}}, "options");
              }),
              HasSubstr("key 'grafting.realizations': must be >= 1, got 0"));
  EXPECT_THAT(errorOf([&] {
                applyRunConfigOverrides(base, {{"ekf.", "1"}}, "options");
              }),
              HasSubstr("override key 'ekf.' is not a dotted key"));
  RunConfigReport unknown;
  applyRunConfigOverrides(base, {{"ekf.gate", "0.5"}}, "options", &unknown);
  EXPECT_EQ(unknown.unknown_keys, (std::vector<std::string>{"ekf.gate"}));
}

TEST(RunConfig, OverrideNodesFromAFileKeepTheirLine) {
  const YAML::Node manifest = YAML::Load("axes:\n  gate: 0.95\n  bad: [1]\n");
  const RunConfig c =
      applyRunConfigOverrides({}, {{"ekf.gate_probability", manifest["axes"]["gate"]}}, "m.yaml");
  EXPECT_EQ(c.ekf.gate_probability, 0.95);
  EXPECT_THAT(
      errorOf([&] {
        applyRunConfigOverrides({}, {{"ekf.gate_probability", manifest["axes"]["bad"]}}, "m.yaml");
      }),
      HasSubstr("m.yaml:3: key 'ekf.gate_probability'"));
}

TEST(RunConfig, SchemaListsEverySection) {
  std::vector<std::string> sections;
  for (const auto& s : runConfigSchema()) sections.push_back(s.first);
  EXPECT_EQ(sections, (std::vector<std::string>{"time_range", "outages", "gnss", "ekf", "grafting",
                                                "fgo", "evaluation", "odometer", "nhc"}));
}

// A time range for a command that does not apply it: the key, the command, the file and the
// bounds it sets are named; no range passes.
TEST(RunConfig, ATimeRangeIsRefusedNamingTheKeyTheCommandAndTheFile) {
  EXPECT_NO_THROW(requireTimeRangeUnset(TimeRangeConfig{}, "R.yaml", "graftnav evaluate"));
  TimeRangeConfig r;
  r.end_s = 456600.5;
  EXPECT_EQ(test::errorOf([&] { requireTimeRangeUnset(r, "R.yaml", "graftnav evaluate"); }),
            "time_range is not applied by graftnav evaluate: the run config 'R.yaml' sets "
            "time_range (end_s 456600.5); remove it to run on the whole recording (graftnav "
            "navigate, compare and real without a latency study apply it)");
  r.start_s = 456400;
  EXPECT_NE(test::errorOf([&] { requireTimeRangeUnset(r, "R.yaml", "graftnav diagnose"); })
                .find("by graftnav diagnose: the run config 'R.yaml' sets time_range (start_s "
                      "456400, end_s 456600.5)"),
            std::string::npos);
}

}  // namespace
}  // namespace graftnav
