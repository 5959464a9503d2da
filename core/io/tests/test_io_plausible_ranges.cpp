// The `plausible_ranges:` block of an IMU profile: the grade's class by default, another class or
// a bound overridden in unit-named keys, converted to SI once.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "graftnav/io/imu_profile_io.h"
#include "graftnav/nav/units.h"
#include "test_support.h"

namespace graftnav {
namespace {

std::string writeProfile(const std::string& body) {
  const std::string path = test::makeTempDir("plausible") + "/p.yaml";
  std::ofstream(path) << "grade: mems\narw_deg_rt_h: 0.5\nvrw_m_s_rt_h: 0.1\n"
                         "gyro_bias_instability_deg_h: 50\naccel_bias_instability_mg: 2\n"
                      << body;
  return path;
}

TEST(IoPlausibleRanges, DefaultIsTheGradesClassAndKeysOverrideInTheirUnits) {
  const ImuProfile d = loadImuProfile(writeProfile(""));
  EXPECT_EQ(d.plausible_ranges.sensor_class, "consumer_mems");
  const ImuProfile p = loadImuProfile(writeProfile(
      "plausible_ranges:\n  sensor_class: industrial_mems\n  accel_scale_max_ppm: 2000\n"
      "  gyro_nonorthogonality_max_deg: 0.1\n  g_sensitivity_max_deg_h_per_g: 36\n"));
  EXPECT_EQ(p.plausible_ranges.sensor_class, "industrial_mems");
  EXPECT_DOUBLE_EQ(p.plausible_ranges.accel_scale_max, 2000e-6);
  EXPECT_NEAR(p.plausible_ranges.gyro_nonorthogonality_max_rad, 0.1 * units::kDegToRad, 1e-15);
  EXPECT_NEAR(p.plausible_ranges.g_sensitivity_max_rad_s_per_m_s2,
              36.0 * units::kDegPerHourToRadPerSec / units::kStandardGravity_m_s2, 1e-15);
  EXPECT_EQ(p.plausible_ranges.gyro_scale_max,
            plausibleRangesForClass("industrial_mems").gyro_scale_max);
}

TEST(IoPlausibleRanges, AnUnknownClassOrANonPositiveBoundNamesFileAndKey) {
  const std::string bad_class = writeProfile("plausible_ranges: {sensor_class: phone}\n");
  try {
    loadImuProfile(bad_class);
    FAIL() << "unknown class accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad_class), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plausible_ranges.sensor_class"), std::string::npos)
        << e.what();
  }
  const std::string zero = writeProfile("plausible_ranges: {gyro_scale_max_ppm: 0}\n");
  try {
    loadImuProfile(zero);
    FAIL() << "zero bound accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gyro_scale_max_ppm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace graftnav
