// Simulator config keys for the field-mounting geometry and the non-linear sensor terms of the
// tested IMU (sim_config.h), as used by the concealed-effects suite: SI conversion in the parser,
// and the lab model without the geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "graftnav/sim/sim_config.h"
#include "graftnav/nav/units.h"
#include "test_support.h"

namespace graftnav {
namespace {

std::string concealed(const std::string& name) {
  return test::sourceDir() + "/configs/sim/concealed/" + name + ".yaml";
}

TEST(SimConfigGeometry, TimeOffsetAndLeverArmParsedAndKeptOutOfTheLab) {
  std::vector<std::string> warnings;
  const SimConfig c = loadSimConfig(concealed("time_offset_lever_arm"), &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_DOUBLE_EQ(c.tested_imu.extra.time_offset.tau_s, 0.003);
  EXPECT_TRUE(c.tested_imu.extra.lever_arm.r_m.isApprox(Eigen::Vector3d(0.05, 0.02, -0.03)));
  const ImuErrorModel field = buildSimErrorModel(c.tested_imu, 5, false);
  EXPECT_DOUBLE_EQ(field.time_offset.tau_s, 0.003);
  EXPECT_TRUE(field.lever_arm.r_m.isApprox(Eigen::Vector3d(0.05, 0.02, -0.03)));
  const ImuErrorModel lab = labErrorModel(field);
  EXPECT_FALSE(lab.hasGeometry());
  // Everything else of the sensor is kept.
  EXPECT_TRUE(lab.gyro.scale_factor.k.isApprox(field.gyro.scale_factor.k));
  EXPECT_TRUE(lab.accel.white_noise.density.isApprox(field.accel.white_noise.density));
  EXPECT_FALSE(buildSimErrorModel(c.tested_imu, 5, true).hasGeometry());  // --ideal
}

TEST(SimConfigGeometry, MisalignmentInDegreesAndAsymmetryInPpm) {
  const SimConfig m = loadSimConfig(concealed("misalignment_gsens"));
  const Eigen::Vector3d rot = m.tested_imu.extra.mounting_misalignment.rotation_rad;
  EXPECT_NEAR(rot(0), -0.2 * M_PI / 180.0, 1e-15);
  EXPECT_NEAR(rot(1), 0.15 * M_PI / 180.0, 1e-15);
  EXPECT_NEAR(buildSimErrorModel(m.tested_imu, 1, false).mounting_misalignment.rotation_rad(2),
              0.1 * M_PI / 180.0, 1e-15);
  const SimConfig a = loadSimConfig(concealed("scale_asymmetry"));
  const ImuErrorModel am = buildSimErrorModel(a.tested_imu, 1, false);
  EXPECT_DOUBLE_EQ(am.gyro.scale_asymmetry.k_pos(2), 1500e-6);
  EXPECT_DOUBLE_EQ(am.gyro.scale_asymmetry.k_neg(2), -1500e-6);
  EXPECT_DOUBLE_EQ(am.gyro.scale_asymmetry.k_pos(0), 0.0);
  // A sensor term stays in the lab model.
  EXPECT_DOUBLE_EQ(labErrorModel(am).gyro.scale_asymmetry.k_pos(2), 1500e-6);
}

}  // namespace
}  // namespace graftnav
