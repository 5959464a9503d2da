// Every subcommand's --help, against the shared flag vocabulary of docs/cli.md: the common flags
// are where they make sense, the old spellings are hidden, and the deprecated ones still work
// with a warning. Also --version's commit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

// Common flags each subcommand must offer (docs/cli.md, "Which command takes which flag").
const std::map<std::string, std::vector<std::string>>& expectedFlags() {
  static const std::map<std::string, std::vector<std::string>> m = {
      {"simulate", {"--sim-config", "--out"}},
      {"navigate",
       {"--out", "--run-config", "--estimator", "--imu", "--profile", "--lenient", "--no-plots",
        "--start", "--end"}},
      {"calibrate", {"--out", "--no-plots"}},
      {"graft", {"--out"}},
      {"evaluate", {"--out", "--run-config", "--estimator", "--no-plots"}},
      {"compare",
       {"--out", "--run-config", "--estimator", "--imu", "--profile", "--lenient", "--no-plots",
        "--start", "--end"}},
      {"batch", {}},
      {"diagnose", {"--out", "--run-config", "--estimator", "--no-plots", "--options"}},
      {"real",
       {"--out", "--run-config", "--estimator", "--imu", "--profile", "--no-plots", "--start",
        "--end"}},
      {"real-sg", {"--out", "--run-config", "--estimator", "--no-plots"}},
      {"import kf-gins", {"--out", "--reference"}},
      {"import ob-gins", {"--out", "--reference"}},
  };
  return m;
}

TEST(CliVocabulary, EveryHelpListsTheCommonFlagsAndNoOldSpelling) {
  for (const auto& [cmd, flags] : expectedFlags()) {
    const test::CommandOutput o = test::runGraftnav(cmd + " --help");
    ASSERT_EQ(o.exit_code, 0) << cmd << ":\n" << o.text;
    for (const auto& f : flags)
      EXPECT_THAT(o.text, HasSubstr(f + " ")) << cmd << " --help lacks " << f;
    EXPECT_THAT(o.text, Not(HasSubstr("--estimators"))) << cmd;
    EXPECT_THAT(o.text, Not(HasSubstr("--config "))) << cmd;
    EXPECT_THAT(o.text, Not(HasSubstr("--free-inertial"))) << cmd;
  }
}

TEST(CliVocabulary, TopLevelHelpListsEverySubcommand) {
  const test::CommandOutput o = test::runGraftnav("--help");
  ASSERT_EQ(o.exit_code, 0) << o.text;
  for (const auto& [cmd, flags] : expectedFlags()) {
    const std::string first = cmd.substr(0, cmd.find(' '));
    EXPECT_THAT(o.text, HasSubstr(first)) << first;
  }
}

// ref, else the case's only IMU (tests/apps/test_case_checks_app.cpp runs it).
TEST(CliVocabulary, ImuDefaultsToRefEverywhere) {
  for (const std::string cmd : {"navigate", "compare", "real"}) {
    const test::CommandOutput o = test::runGraftnav(cmd + " --help");
    const size_t at = o.text.find("--imu");
    ASSERT_NE(at, std::string::npos) << cmd;
    const std::string line = o.text.substr(at, o.text.find('\n', at) - at);
    EXPECT_NE(line.find("default: ref, else the case's only IMU"), std::string::npos)
        << cmd << ": " << line;
  }
}

TEST(CliVocabulary, OldSpellingsWarnAndStillWork) {
  const std::string sample = test::sourceDir() + "/data/sample_mems";
  const std::string out = test::makeTempDir("cli_deprecated");
  const test::CommandOutput o =
      test::runGraftnav("navigate " + sample + " --out " + out + " --no-plots --config " +
                        test::sourceDir() + "/configs/navigate.yaml --estimator ekf");
  ASSERT_EQ(o.exit_code, 0) << o.text;
  EXPECT_THAT(o.text, HasSubstr("warning: --config is deprecated, use --run-config"));
  // The config was applied: its 60 s outages every 180 s from 300 s give 3 in the 870 s sample.
  EXPECT_THAT(o.text, HasSubstr("outages (3)"));
  const test::CommandOutput s = test::runGraftnav("simulate --out " + out + "/sim");
  EXPECT_NE(s.exit_code, 0);
  EXPECT_THAT(s.text, HasSubstr("--sim-config"));
}

TEST(CliVocabulary, PeerSetupGivenAsRunConfigIsRefusedWithTheImportHint) {
  const std::string sample = test::sourceDir() + "/data/sample_mems";
  const std::string out = test::makeTempDir("cli_peer_config");
  FILE* f = std::fopen((out + "/kf-gins.yaml").c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("imupath: imu.txt\ngnsspath: gnss.txt\nimudatarate: 200\n", f);
  std::fclose(f);
  const test::CommandOutput o =
      test::runGraftnav("navigate " + sample + " --out " + out + "/o --no-plots --run-config " +
                        out + "/kf-gins.yaml");
  EXPECT_NE(o.exit_code, 0);
  EXPECT_THAT(o.text, HasSubstr("graftnav import kf-gins|ob-gins"));
  EXPECT_THAT(o.text, HasSubstr("kf-gins.yaml:1"));
}

TEST(CliVocabulary, RelativePathErrorNamesEveryPathTried) {
  const std::string sample = test::sourceDir() + "/data/sample_mems";
  const std::string out = test::makeTempDir("cli_paths");
  const test::CommandOutput o = test::runGraftnav("navigate " + sample + " --out " + out +
                                                  " --no-plots --imu no_such_imu.txt");
  EXPECT_NE(o.exit_code, 0);
  EXPECT_THAT(o.text, HasSubstr("IMU file 'no_such_imu.txt' not found; tried"));
  EXPECT_THAT(o.text, HasSubstr("sample_mems/no_such_imu.txt"));
}

TEST(CliVocabulary, VersionCarriesTheGitCommit) {
  const test::CommandOutput o = test::runGraftnav("--version");
  ASSERT_EQ(o.exit_code, 0) << o.text;
  EXPECT_THAT(o.text,
              ::testing::MatchesRegex(
                  "graftnav [0-9]+\\.[0-9]+\\.[0-9]+ \\(commit [0-9a-f]{12}(-dirty)?\\)\n"));
}

}  // namespace
}  // namespace graftnav
