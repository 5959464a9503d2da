// The run config's odometer and nhc sections: units converted once (ppm, degrees), a scalar or a
// list for the stds, errors naming the source, line and key; makeProblem hands the options to
// the estimators with the case's field/odometer.txt as a stream, refuses an enabled odometer
// without the file and warns with the spans an odometer leaves uncovered.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "graftnav/case/problem.h"
#include "graftnav/case/run_config.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/nav/units.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

using test::errorOf;

TEST(AidingConfig, SectionsFillTheOptionsInSiUnits) {
  RunConfigReport report;
  const RunConfig c = parseRunConfigText(
      "odometer:\n  enabled: true\n  std_m_s: 0.02\n  scale_std_ppm: 5000\n"
      "  scale_random_walk_ppm_sqrt_s: 2\n  lever_arm_m: [-0.5, 0.2, 0.8]\n"
      "  mounting_deg: [0, -0.3, 1.5]\n  rate_hz: 5\n  forward_only: false\n"
      "nhc: {enabled: true, std_m_s: [0.2, 0.3]}\n",
      "options", &report);
  EXPECT_TRUE(report.warnings.empty());
  const VehicleAidingOptions& a = c.aiding.options;
  EXPECT_TRUE(a.odometer.enabled && a.nhc.enabled);
  EXPECT_EQ(a.odometer.std_m_s, Eigen::Vector3d(0.02, 0.0, 0.0));  // a scalar: forward only
  EXPECT_NEAR(a.odometer.scale_std, 5000e-6, 1e-15);
  EXPECT_NEAR(a.odometer.scale_random_walk_per_sqrt_s, 2e-6, 1e-18);
  EXPECT_NEAR(a.odometer.mounting_rad.z(), 1.5 * units::kDegToRad, 1e-15);
  EXPECT_EQ(a.odometer.lever_arm_b_m.x(), -0.5);
  EXPECT_EQ(a.nhc.std_m_s, Eigen::Vector2d(0.2, 0.3));
  EXPECT_EQ(a.rateHz(), 10.0);  // the larger of the two sections' rates
  EXPECT_EQ(a.rowStd_m_s(), Eigen::Vector3d(0.02, 0.2, 0.3));
  EXPECT_FALSE(c.aiding.odometer_read.forward_only);
  // OB_GINS's three-axis std; NHC's scalar applies to both rows.
  const RunConfig d = parseRunConfigText(
      "odometer: {enabled: true, std_m_s: [0.05, 0.1, 0.2]}\nnhc: {std_m_s: 0.4}\n", "options");
  EXPECT_EQ(d.aiding.options.odometer.std_m_s, Eigen::Vector3d(0.05, 0.1, 0.2));
  EXPECT_EQ(d.aiding.options.nhc.std_m_s, Eigen::Vector2d(0.4, 0.4));
  EXPECT_FALSE(RunConfig{}.aiding.options.any());  // off unless enabled
}

TEST(AidingConfig, BadValuesNameTheSourceLineAndKey) {
  EXPECT_THAT(errorOf([] { parseRunConfigText("odometer:\n  std_m_s: -1\n", "r.yaml"); }),
              HasSubstr("r.yaml:2: key 'odometer.std_m_s'"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("nhc:\n  std_m_s: [0.1]\n", "r.yaml"); }),
              HasSubstr("key 'nhc.std_m_s'"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("odometer: {scale_std_ppm: 600000}\n", "r.yaml"); }),
              HasSubstr("odometer.scale_std_ppm"));
  EXPECT_THAT(errorOf([] { parseRunConfigText("odometer: {rate_hz: 0}\n", "r.yaml"); }),
              HasSubstr("odometer.rate_hz"));
  RunConfigReport report;
  parseRunConfigText("nhc: {enabled: true, rate: 5}\n", "r.yaml", &report);
  EXPECT_EQ(report.unknown_keys, std::vector<std::string>{"nhc.rate"});
}

TEST(AidingConfig, MakeProblemStreamsTheCaseOdometerAndWarnsOnGaps) {
  const std::string dir = test::makeTempDir("aiding_problem");
  fs::copy(test::sourceDir() + "/data/sample_tactical", dir + "/case", fs::copy_options::recursive);
  CaseInputs c = loadCaseInputs(dir + "/case");
  const ImuSelection imu = selectImu(c, "ref");
  RunConfig rc = parseRunConfigText("odometer: {enabled: true}\nnhc: {enabled: true}\n", "r");
  EXPECT_THAT(errorOf([&] { makeProblem(c, imu, rc, std::nullopt, nullptr); }),
              HasSubstr("no field/odometer.txt"));
  // An odometer over the first half of the IMU span only, at 10 Hz.
  const double t0 = imu.imu.front().t_s, t1 = imu.imu.back().t_s;
  OdometerSeries odo;
  for (double t = t0; t < 0.5 * (t0 + t1); t += 0.1) odo.push_back({t, 5.0});
  writeOdometer(c.paths().odometer(), odo);
  std::vector<std::string> notes;
  const EstimationProblem p = makeProblem(c, imu, rc, std::nullopt, &notes);
  EXPECT_TRUE(p.aiding.odometer.enabled && p.aiding.nhc.enabled);
  ASSERT_TRUE(p.odometer_stream);
  auto pass = p.openOdometer();
  OdometerSample s;
  int n = 0;
  while (pass->next(&s)) ++n;
  EXPECT_EQ(n, static_cast<int>(odo.size()));
  bool warned = false;
  for (const auto& note : notes)
    warned = warned || (note.find("WARNING") != std::string::npos &&
                        note.find("odometer.txt does not cover") != std::string::npos);
  EXPECT_TRUE(warned);
  // NHC alone needs no odometer file.
  fs::remove(c.paths().odometer());
  rc = parseRunConfigText("nhc: {enabled: true}\n", "r");
  EXPECT_TRUE(makeProblem(c, imu, rc, std::nullopt, nullptr).aiding.nhc.enabled);
}

}  // namespace
}  // namespace graftnav
