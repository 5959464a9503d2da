// case.yaml parsing (spec example, real files, errors), writer round trip, CasePaths, IMU profiles.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "graftnav/io/case_config.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/nav/rotation.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

void writeText(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream f(path, std::ios::binary);
  f << text;
}

const char* kSpecExample = R"(name: mems_case_01
imu_rate_hz: 200
tested_imu_rate_hz: 200                 # optional
reference_solution: field/reference.nav # optional
reference_imu: {grade: navigation, arw_deg_rt_h: 0.0022, vrw_m_s_rt_h: 0.00075, gyro_bias_instability_deg_h: 0.005, accel_bias_instability_mg: 0.025}
tested_imu:    {grade: mems, arw_deg_rt_h: 0.15, vrw_m_s_rt_h: 0.06, gyro_bias_instability_deg_h: 10, accel_bias_instability_mg: 1.0, gyro_scale_ppm: 1000}
lever_arm_m: [0.0, 0.0, -1.2]
gnss: {week: 2100}
initial_state:
  time: 456300.0
  position: [30.4447873701, 114.4718632047, 20.899]
  velocity_ned: [0.0, 0.0, 0.0]
  attitude_deg: [0.85, -2.03, 185.70]
lab:
  latitude_deg: 30.53
  height_m: 25.0
  static: {attitude_deg: [0.0, 0.0, 0.0]}
  six_position:
    x_up: [0.0, 90.0, 0.0]
  rate_table: {axis_up: true}
  tilt: {t1: [10.0, 0.0, 45.0]}
)";

TEST(IoCaseConfig, ParsesSpecExampleIntoSi) {
  const std::string path = test::makeTempDir("io") + "/case.yaml";
  writeText(path, kSpecExample);
  std::vector<std::string> warnings;
  const CaseConfig c = loadCaseConfig(path, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(c.name, "mems_case_01");
  EXPECT_DOUBLE_EQ(c.imu_rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(c.testedImuRateHz(), 200.0);
  EXPECT_EQ(c.reference_solution.value(), "field/reference.nav");
  ASSERT_TRUE(c.reference_imu && c.tested_imu);
  EXPECT_TRUE(c.reference_imu_noise_given && c.tested_imu_noise_given);
  EXPECT_EQ(c.tested_imu->grade, ImuGrade::kMems);
  EXPECT_NEAR(c.tested_imu->arw_rad_sqrt_s, 0.15 * kDeg / 60.0, 1e-18);
  EXPECT_NEAR(c.tested_imu->vrw_m_s_sqrt_s, 0.06 / 60.0, 1e-18);
  EXPECT_NEAR(c.tested_imu->gyro_bias_instability_rad_s, 10.0 * kDeg / 3600.0, 1e-18);
  EXPECT_NEAR(c.tested_imu->accel_bias_instability_m_s2, 1.0e-3 * 9.80665, 1e-18);
  EXPECT_NEAR(c.tested_imu->gyro_scale_std, 1000e-6, 1e-18);
  EXPECT_EQ(c.tested_imu->accel_scale_std, 0.0);
  EXPECT_NEAR(c.reference_imu->accel_bias_instability_m_s2, 0.025e-3 * 9.80665, 1e-18);
  EXPECT_EQ(c.lever_arm_m.value(), Eigen::Vector3d(0, 0, -1.2));
  EXPECT_EQ(c.gnss_week.value(), 2100);
  ASSERT_TRUE(c.initial_state);
  EXPECT_EQ(c.initial_state->gnss_week, 2100);
  EXPECT_DOUBLE_EQ(c.initial_state->t_s, 456300.0);
  EXPECT_NEAR(c.initial_state->pos.lat_rad, 30.4447873701 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(c.initial_state->pos.h_m, 20.899);
  const Eigen::Vector3d e = eulerFromQuat(c.initial_state->q_nb) / kDeg;
  EXPECT_NEAR(e.x(), 0.85, 1e-10);
  EXPECT_NEAR(e.y(), -2.03, 1e-10);
  EXPECT_NEAR(e.z(), 185.70 - 360.0, 1e-10);
  ASSERT_TRUE(c.lab);
  EXPECT_NEAR(c.lab->latitude_rad, 30.53 * kDeg, 1e-15);
  EXPECT_EQ(c.lab->static_euler_rad.value(), Eigen::Vector3d::Zero());
  ASSERT_EQ(c.lab->six_position_euler_rad.count("x_up"), 1u);
  EXPECT_NEAR(c.lab->six_position_euler_rad.at("x_up").y(), kPi / 2, 1e-15);
  EXPECT_TRUE(c.lab->rate_table_axis_up.value());
  EXPECT_NEAR(c.lab->tilt_euler_rad.at("t1").z(), kPi / 4, 1e-15);
}

TEST(IoCaseConfig, WriterRoundTrip) {
  const std::string dir = test::makeTempDir("io");
  writeText(dir + "/in.yaml", kSpecExample);
  const CaseConfig c = loadCaseConfig(dir + "/in.yaml");
  saveCaseConfig(dir + "/out.yaml", c);
  std::vector<std::string> warnings;
  const CaseConfig b = loadCaseConfig(dir + "/out.yaml", &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(b.name, c.name);
  EXPECT_EQ(b.imu_rate_hz, c.imu_rate_hz);
  EXPECT_EQ(b.tested_imu_rate_hz, c.tested_imu_rate_hz);
  EXPECT_EQ(b.reference_solution, c.reference_solution);
  EXPECT_NEAR(b.tested_imu->arw_rad_sqrt_s, c.tested_imu->arw_rad_sqrt_s,
              1e-14 * c.tested_imu->arw_rad_sqrt_s);
  EXPECT_NEAR(b.tested_imu->gyro_scale_std, c.tested_imu->gyro_scale_std, 1e-18);
  EXPECT_NEAR(b.reference_imu->accel_bias_instability_m_s2,
              c.reference_imu->accel_bias_instability_m_s2, 1e-18);
  EXPECT_EQ(b.gnss_week, c.gnss_week);
  EXPECT_TRUE(b.lever_arm_m->isApprox(*c.lever_arm_m));
  EXPECT_NEAR(b.initial_state->pos.lat_rad, c.initial_state->pos.lat_rad, 1e-14);
  EXPECT_LT(b.initial_state->q_nb.angularDistance(c.initial_state->q_nb), 1e-12);
  EXPECT_NEAR(b.lab->latitude_rad, c.lab->latitude_rad, 1e-15);
  EXPECT_EQ(b.lab->six_position_euler_rad.size(), 1u);
  EXPECT_EQ(b.lab->tilt_euler_rad.size(), 1u);
  EXPECT_EQ(b.lab->rate_table_axis_up, c.lab->rate_table_axis_up);
}

TEST(IoCaseConfig, UnknownKeysAreWarningsErrorsNameKey) {
  const std::string dir = test::makeTempDir("io");
  writeText(
      dir + "/extra.yaml",
      "name: a\nimu_rate_hz: 100\ncolour: red\nlab: {latitude_deg: 1, height_m: 2, foo: 3}\n");
  std::vector<std::string> warnings;
  loadCaseConfig(dir + "/extra.yaml", &warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_THAT(warnings[0], HasSubstr("extra.yaml:3: unknown key 'colour'"));
  EXPECT_THAT(warnings[1], HasSubstr("unknown key 'lab.foo'"));

  struct Case {
    std::string name, text, fragment;
  };
  const std::vector<Case> cases = {
      {"missing_rate", "name: a\n", "missing required key 'imu_rate_hz'"},
      {"missing_name", "imu_rate_hz: 100\n", "missing required key 'name'"},
      {"bad_rate", "name: a\nimu_rate_hz: fast\n",
       ":2: key 'imu_rate_hz': expected a number, got 'fast'"},
      {"bad_lever", "name: a\nimu_rate_hz: 100\nlever_arm_m: [1, 2]\n",
       ":3: key 'lever_arm_m': expected a list of 3"},
      {"bad_week", "name: a\nimu_rate_hz: 100\ngnss: {week: 21.5}\n",
       "key 'gnss.week': expected an integer"},
      {"lab_missing", "name: a\nimu_rate_hz: 100\nlab: {height_m: 2}\n",
       "missing required key 'lab.latitude_deg'"},
      {"partial_noise", "name: a\nimu_rate_hz: 100\ntested_imu: {grade: mems, arw_deg_rt_h: 0.1}\n",
       "missing required key 'tested_imu.vrw_m_s_rt_h'"},
      {"bad_grade", "name: a\nimu_rate_hz: 100\ntested_imu: {grade: good}\n",
       "key 'tested_imu.grade'"},
      {"bad_pose",
       "name: a\nimu_rate_hz: 100\nlab: {latitude_deg: 1, height_m: 2, six_position: {x_side: [0,0,0]}}\n",
       "lab.six_position.x_side"},
      {"init_missing",
       "name: a\nimu_rate_hz: 100\ninitial_state: {time: 1, position: [1,2,3], velocity_ned: [0,0,0]}\n",
       "missing required key 'initial_state.attitude_deg'"},
      {"syntax", "name: a\nimu_rate_hz: [100\n", "YAML syntax error"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".yaml";
    writeText(path, c.text);
    try {
      loadCaseConfig(path);
      ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr(path));
      EXPECT_THAT(std::string(e.what()), HasSubstr(c.fragment));
    }
  }
  EXPECT_THROW(loadCaseConfig(dir + "/missing.yaml"), std::runtime_error);
}

TEST(IoCaseConfig, AllRealCaseFilesParse) {
  const std::filesystem::path real = std::filesystem::path(test::sharedDir()) / "data" / "real";
  GRAFTNAV_REQUIRE_SHARED_PATH(real.string());
  int parsed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(real)) {
    const auto yaml = entry.path() / "case.yaml";
    if (!std::filesystem::exists(yaml)) continue;
    SCOPED_TRACE(yaml.string());
    std::vector<std::string> warnings;
    const CaseConfig c = loadCaseConfig(yaml.string(), &warnings);
    EXPECT_EQ(c.name, entry.path().filename().string());
    EXPECT_GT(c.imu_rate_hz, 0.0);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    ++parsed;
    if (c.name == "yandld_20220405_rtk") {
      EXPECT_EQ(c.gnss_week.value(), 2204);
      EXPECT_EQ(c.reference_solution.value(), "field/reference.nav");
      EXPECT_FALSE(c.reference_imu.has_value());
      ASSERT_TRUE(c.tested_imu.has_value());
      EXPECT_FALSE(c.tested_imu_noise_given);
      EXPECT_NEAR(c.initial_state->pos.lat_rad, 40.2024085 * kDeg, 1e-15);
    }
    if (c.name == "wid_car_trial07") {
      EXPECT_DOUBLE_EQ(c.testedImuRateHz(), 120.0);
    }
    if (c.name == "imucal_ferraris") {
      EXPECT_DOUBLE_EQ(c.imu_rate_hz, 102.4);
      EXPECT_TRUE(c.lab->rate_table_axis_up.value());
      const auto rates = CasePaths(entry.path().string()).rateFiles();
      ASSERT_EQ(rates.size(), 3u);
      EXPECT_EQ(rates[0].axis, 0);
      EXPECT_EQ(rates[0].sign, -1);
      EXPECT_DOUBLE_EQ(rates[2].rate_deg_s, 120.0);
    }
  }
  EXPECT_GE(parsed, 4);
}

TEST(IoCasePaths, StandardPathsAndRateNames) {
  const CasePaths p("/data/case1");
  EXPECT_EQ(p.refImu(), "/data/case1/field/ref_imu.txt");
  EXPECT_EQ(p.testedImu(), "/data/case1/field/tested_imu.txt");
  EXPECT_EQ(p.gnssPos(), "/data/case1/field/gnss.pos");
  EXPECT_EQ(p.gnssFixType(), "/data/case1/field/gnss_fixtype.txt");
  EXPECT_EQ(p.truthNav(), "/data/case1/field/truth.nav");
  EXPECT_EQ(p.labStatic(), "/data/case1/lab/static.txt");
  EXPECT_EQ(p.sixPosition(1, false), "/data/case1/lab/six_position/y_down.txt");
  EXPECT_EQ(p.tilt("t1"), "/data/case1/lab/tilt/t1.txt");
  EXPECT_THROW(p.sixPosition(3, true), std::invalid_argument);
  const auto r = parseRateFileName("z_neg_30.txt");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->axis, 2);
  EXPECT_EQ(r->sign, -1);
  EXPECT_NEAR(r->rate_rad_s(), -30.0 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(parseRateFileName("x_pos_2.5.txt")->rate_deg_s, 2.5);
  EXPECT_FALSE(parseRateFileName("w_pos_30.txt"));
  EXPECT_FALSE(parseRateFileName("x_up_30.txt"));
  EXPECT_FALSE(parseRateFileName("x_pos_0.txt"));
  EXPECT_FALSE(parseRateFileName("x_pos_30.csv"));

  const std::string dir = test::makeTempDir("io");
  for (const char* n : {"z_pos_10.txt", "x_neg_100.txt", "x_neg_20.txt", "x_pos_5.txt"})
    writeText(dir + "/lab/rate/" + n, "");
  const auto files = CasePaths(dir).rateFiles();
  ASSERT_EQ(files.size(), 4u);
  EXPECT_DOUBLE_EQ(files[0].rate_deg_s, 20.0);  // x neg 20, x neg 100, x pos 5, z pos 10
  EXPECT_DOUBLE_EQ(files[1].rate_deg_s, 100.0);
  EXPECT_EQ(files[2].sign, 1);
  EXPECT_EQ(files[3].axis, 2);
  writeText(dir + "/lab/rate/x_fast.txt", "");
  EXPECT_THROW(CasePaths(dir).rateFiles(), std::runtime_error);
  EXPECT_TRUE(CasePaths(test::makeTempDir("io_empty")).rateFiles().empty());
}

TEST(IoImuProfile, ConfigsHoldTable1InSi) {
  const std::string dir = test::sourceDir() + "/configs/imu/";
  const ImuProfile mems = loadImuProfile(dir + "pos1100_mems.yaml");
  EXPECT_EQ(mems.grade, ImuGrade::kMems);
  EXPECT_EQ(mems.name, "POS1100-like");
  EXPECT_NEAR(mems.arw_rad_sqrt_s, 0.15 * kPi / 180.0 / 60.0, 1e-18);
  EXPECT_NEAR(mems.vrw_m_s_sqrt_s, 0.06 / 60.0, 1e-18);
  EXPECT_NEAR(mems.gyro_bias_instability_rad_s, 10.0 * kPi / 180.0 / 3600.0, 1e-18);
  EXPECT_NEAR(mems.accel_bias_instability_m_s2, 1e-3 * 9.80665, 1e-18);
  EXPECT_NEAR(mems.gyro_scale_std, 1000e-6, 1e-18);
  EXPECT_NEAR(mems.accel_scale_std, 1000e-6, 1e-18);
  EXPECT_DOUBLE_EQ(mems.gyro_bias_corr_time_s, 3600.0);
  EXPECT_DOUBLE_EQ(mems.gyro_bias_initial_std_rad_s, mems.gyro_bias_instability_rad_s);

  const ImuProfile tac = loadImuProfile(dir + "pos310_tactical.yaml");
  EXPECT_EQ(tac.grade, ImuGrade::kTactical);
  EXPECT_NEAR(tac.gyro_bias_instability_rad_s, 0.5 * kPi / 180.0 / 3600.0, 1e-18);
  EXPECT_NEAR(tac.arw_rad_sqrt_s, 0.05 * kPi / 180.0 / 60.0, 1e-18);
  EXPECT_NEAR(tac.accel_bias_instability_m_s2, 0.5e-3 * 9.80665, 1e-18);
  EXPECT_NEAR(tac.vrw_m_s_sqrt_s, 0.1 / 60.0, 1e-18);
  EXPECT_NEAR(tac.gyro_scale_std, 300e-6, 1e-18);

  const ImuProfile nav = loadImuProfile(dir + "pos830_navigation.yaml");
  EXPECT_EQ(nav.grade, ImuGrade::kNavigation);
  EXPECT_NEAR(nav.gyro_bias_instability_rad_s, 0.005 * kPi / 180.0 / 3600.0, 1e-18);
  EXPECT_NEAR(nav.arw_rad_sqrt_s, 0.0022 * kPi / 180.0 / 60.0, 1e-18);
  EXPECT_NEAR(nav.accel_bias_instability_m_s2, 0.025e-3 * 9.80665, 1e-18);
  EXPECT_NEAR(nav.vrw_m_s_sqrt_s, 0.00075 / 60.0, 1e-18);
  EXPECT_NEAR(nav.accel_scale_std, 10e-6, 1e-18);
}

TEST(IoImuProfile, RoundTripAndErrors) {
  const std::string dir = test::makeTempDir("io");
  ImuProfile p = loadImuProfile(test::sourceDir() + "/configs/imu/pos310_tactical.yaml");
  p.accel_bias_corr_time_s = 600.0;
  p.gyro_bias_initial_std_rad_s = 3.0 * p.gyro_bias_instability_rad_s;
  saveImuProfile(dir + "/p.yaml", p);
  const ImuProfile b = loadImuProfile(dir + "/p.yaml");
  EXPECT_EQ(b.name, p.name);
  EXPECT_NEAR(b.arw_rad_sqrt_s, p.arw_rad_sqrt_s, 1e-14 * p.arw_rad_sqrt_s);
  EXPECT_NEAR(b.accel_bias_instability_m_s2, p.accel_bias_instability_m_s2,
              1e-14 * p.accel_bias_instability_m_s2);
  EXPECT_NEAR(b.gyro_bias_initial_std_rad_s, p.gyro_bias_initial_std_rad_s,
              1e-14 * p.gyro_bias_initial_std_rad_s);
  EXPECT_DOUBLE_EQ(b.accel_bias_corr_time_s, 600.0);
  EXPECT_DOUBLE_EQ(b.gyro_bias_corr_time_s, 3600.0);

  writeText(dir + "/missing_key.yaml",
            "grade: mems\narw_deg_rt_h: 0.1\nvrw_m_s_rt_h: 0.1\naccel_bias_instability_mg: 1\n");
  try {
    loadImuProfile(dir + "/missing_key.yaml");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("missing_key.yaml"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("gyro_bias_instability_deg_h"));
  }
  writeText(dir + "/negative.yaml",
            "grade: mems\narw_deg_rt_h: -0.1\nvrw_m_s_rt_h: 0.1\ngyro_bias_instability_deg_h: 1\n"
            "accel_bias_instability_mg: 1\nunits_note: x\n");
  EXPECT_THAT([&] { loadImuProfile(dir + "/negative.yaml"); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  HasSubstr("negative.yaml:2: key 'arw_deg_rt_h': must be >= 0")));
  writeText(dir + "/unknown.yaml",
            "grade: mems\narw_deg_rt_h: 0.1\nvrw_m_s_rt_h: 0.1\ngyro_bias_instability_deg_h: 1\n"
            "accel_bias_instability_mg: 1\nunits_note: x\n");
  std::vector<std::string> warnings;
  loadImuProfile(dir + "/unknown.yaml", &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("unknown.yaml:6: unknown key 'units_note'"));
}

}  // namespace
}  // namespace graftnav
