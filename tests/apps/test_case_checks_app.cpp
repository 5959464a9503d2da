// The commands on cases a new user brings: a real recording of one IMU (only
// field/tested_imu.txt), a case.yaml with a key graftnav does not know, and a lab static record too
// short to graft from. Each command treats them alike: the one IMU is navigated and named, the
// unknown key is a warning, and the short record is refused before any result is written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

// A copy of a bundled sample case in a fresh folder.
std::string copySample(const std::string& sample, const std::string& tag) {
  const std::string dir = test::makeTempDir(tag) + "/case";
  fs::copy(test::sourceDir() + "/data/" + sample, dir, fs::copy_options::recursive);
  return dir;
}

TEST(CaseChecksApp, CaseWithOnlyTheTestedImuIsNavigatedWithIt) {
  const std::string dir = copySample("sample_mems", "one_imu");
  fs::remove(dir + "/field/ref_imu.txt");
  const test::CommandOutput n =
      test::runGraftnav("navigate " + dir + " --out " + dir + "/nav --estimator ekf --no-plots");
  ASSERT_EQ(n.exit_code, 0) << n.text;
  EXPECT_THAT(n.text, HasSubstr("note: IMU: 'tested'"));
  EXPECT_THAT(n.text, Not(HasSubstr("not found")));
  EXPECT_TRUE(fs::exists(dir + "/nav/solution.nav"));

  const test::CommandOutput r =
      test::runGraftnav("real " + dir + " --out " + dir + "/real --estimator ekf --no-plots " +
                        "--run-config " + test::sourceDir() + "/configs/navigate.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_THAT(r.text, HasSubstr("note: IMU: 'tested'"));
  EXPECT_THAT(r.text, HasSubstr("IMU 'tested'"));
  EXPECT_TRUE(fs::exists(dir + "/real/summary.json"));

  // A case with both IMUs still defaults to the reference IMU, silently.
  const std::string both = copySample("sample_mems", "two_imus");
  const test::CommandOutput b =
      test::runGraftnav("navigate " + both + " --out " + both + "/nav --estimator ekf --no-plots");
  ASSERT_EQ(b.exit_code, 0) << b.text;
  EXPECT_THAT(b.text, Not(HasSubstr("note: IMU:")));
  EXPECT_THAT(b.text, HasSubstr("reading the case and the ref IMU"));
}

TEST(CaseChecksApp, CalibrateWarnsAboutAnUnknownCaseKey) {
  const std::string dir = copySample("sample_tactical", "calib_unknown_key");
  std::ofstream(dir + "/case.yaml", std::ios::app) << "lab_bench: 3\n";
  const test::CommandOutput o =
      test::runGraftnav("calibrate " + dir + " --out " + dir + "/calib --no-plots");
  ASSERT_EQ(o.exit_code, 0) << o.text;
  EXPECT_THAT(o.text, HasSubstr("warning: " + dir + "/case.yaml:"));
  EXPECT_THAT(o.text, HasSubstr("unknown key 'lab_bench' ignored"));
  // The same case through navigate warns the same way.
  const test::CommandOutput n =
      test::runGraftnav("navigate " + dir + " --out " + dir + "/nav --estimator ekf --no-plots");
  EXPECT_THAT(n.text, HasSubstr("unknown key 'lab_bench' ignored"));
}

// lab/static.txt cut to its first 0.1 s: every command that grafts or calibrates from it stops
// with the evaluate's floor message and writes no result.
TEST(CaseChecksApp, ShortLabStaticRecordIsRefusedByEveryLabCommand) {
  const std::string dir = copySample("sample_tactical", "short_static");
  {
    std::ifstream in(dir + "/lab/static.txt");
    std::ostringstream kept;
    std::string line;
    double t0 = -1.0;
    while (std::getline(in, line)) {
      const double t = std::stod(line);
      if (t0 < 0.0) t0 = t - 0.02;
      if (t - t0 > 0.1 + 1e-9) break;
      kept << line << "\n";
    }
    in.close();
    std::ofstream(dir + "/lab/static.txt") << kept.str();
  }
  for (const std::string cmd : {"calibrate", "graft", "diagnose", "evaluate"}) {
    const std::string out = dir + "/out_" + cmd;
    const test::CommandOutput o = test::runGraftnav(cmd + " " + dir + " --out " + out +
                                                    (cmd == "graft" ? "" : " --no-plots"));
    EXPECT_NE(o.exit_code, 0) << cmd << ": " << o.text;
    EXPECT_THAT(
        o.text,
        HasSubstr("lab/static.txt: the lab static record lasts 0.10 s, below the 60 s floor"))
        << cmd;
    EXPECT_FALSE(fs::exists(out + "/calibration.yaml")) << cmd;
    EXPECT_FALSE(fs::exists(out + "/IMU_SG1.txt")) << cmd;
    EXPECT_FALSE(fs::exists(out + "/diagnosis.json")) << cmd;
  }
}

}  // namespace
}  // namespace graftnav
