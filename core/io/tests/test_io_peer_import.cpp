// KF-GINS / OB_GINS set-ups: unit conversion of every noise key, per-axis values, path rules,
// OB_GINS's outage schedule and missing initial position, GNSS gap windows, the written case.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "graftnav/io/case_config.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/io/peer_config.h"
#include "graftnav/io/peer_import.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

void writeText(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}

// Two small data files (content only matters to the importer's GNSS read).
void writeData(const std::string& dir) {
  writeText(dir + "/imu.txt", "100.01 0 0 0 0 0 -0.098\n100.02 0 0 0 0 0 -0.098\n");
  std::string gnss;
  for (int t : {100, 101, 102, 103, 120, 121, 122})
    gnss += std::to_string(t) + " 30.0 114.0 20.0 0.01 0.01 0.02\n";
  writeText(dir + "/gnss.pos", gnss);
}

const char* kKfGins = R"(imupath: "imu.txt"
gnsspath: "gnss.pos"
outputpath: "./out"
imudatalen: 7
imudatarate: 100
starttime: 100
endtime: -1
initpos: [30.0, 114.0, 20.0]
initvel: [1.0, 2.0, 0.0]
initatt: [1.0, -2.0, 90.0]
initgyrbias: [0, 0, 5]
initposstd: [0.1, 0.2, 0.3]
initvelstd: [0.01, 0.01, 0.01]
initattstd: [0.1, 0.1, 0.5]
imunoise:
  arw: [0.2, 0.2, 0.2]
  vrw: [0.06, 0.06, 0.06]
  gbstd: [10.0, 10.0, 20.0]
  abstd: [500.0, 500.0, 500.0]
  gsstd: [300.0, 300.0, 300.0]
  asstd: [100.0, 100.0, 100.0]
  corrtime: 2.0
antlever: [0.1, -0.3, -0.2]
)";

TEST(PeerConfig, KfGinsUnitsConvertedToSi) {
  const std::string dir = test::makeTempDir("peer_kf");
  writeData(dir);
  writeText(dir + "/kf.yaml", kKfGins);
  std::vector<std::string> warnings;
  const PeerSetup s = loadPeerConfig(PeerFormat::kKfGins, dir + "/kf.yaml", &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_NEAR(s.profile.arw_rad_sqrt_s, 0.2 * kDeg / 60.0, 1e-15);
  EXPECT_NEAR(s.profile.vrw_m_s_sqrt_s, 0.06 / 60.0, 1e-15);
  EXPECT_NEAR(s.profile.gyro_bias_instability_rad_s,
              std::sqrt((100.0 + 100.0 + 400.0) / 3.0) * kDeg / 3600.0, 1e-15);
  EXPECT_NEAR(s.profile.accel_bias_instability_m_s2, 500e-5, 1e-15);  // mGal
  EXPECT_NEAR(s.profile.gyro_scale_std, 300e-6, 1e-15);
  EXPECT_NEAR(s.profile.accel_scale_std, 100e-6, 1e-15);
  EXPECT_DOUBLE_EQ(s.profile.gyro_bias_corr_time_s, 7200.0);
  EXPECT_NEAR(s.initial_position->lat_rad, 30.0 * kDeg, 1e-15);
  EXPECT_NEAR(s.initial_euler_rad.z(), 90.0 * kDeg, 1e-15);
  EXPECT_EQ(*s.lever_arm_m, Eigen::Vector3d(0.1, -0.3, -0.2));
  EXPECT_FALSE(s.end_s);
  std::string notes;
  for (const auto& n : s.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("imunoise.gbstd: per-axis values"));
  EXPECT_THAT(notes, HasSubstr("NOT CONVERTED: initgyrbias"));
}

TEST(PeerConfig, ErrorsNameKeyAndLine) {
  const std::string dir = test::makeTempDir("peer_err");
  writeData(dir);
  std::string bad = kKfGins;
  bad.replace(bad.find("corrtime: 2.0"), 13, "corrtime: soon");
  writeText(dir + "/kf.yaml", bad);
  try {
    loadPeerConfig(PeerFormat::kKfGins, dir + "/kf.yaml");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("imunoise.corrtime"));
    EXPECT_THAT(e.what(), HasSubstr("kf.yaml:22"));
  }
  EXPECT_THROW(peerFormatFromName("kf_gins"), std::invalid_argument);
}

TEST(PeerConfig, ObGinsScheduleAndInitialPositionFromGnss) {
  const std::string dir = test::makeTempDir("peer_ob");
  writeData(dir);
  writeText(
      dir + "/ob.yaml",
      "imufile: imu.txt\ngnssfile: gnss.pos\nwindows: 20\nstarttime: 100\nendtime: 0\n"
      "initvel: [0, 0, 0]\ninitatt: [0, 0, 0]\nimudatalen: 7\nimudatarate: 100\nisearth: true\n"
      "antlever: [0, 0, -1.0]\nimumodel: {arw: 0.24, vrw: 0.24, gbstd: 50.0, abstd: 250.0, corrtime: 1.0}\n"
      "isuseoutage: true\noutagetime: 10\noutagelen: 5\noutageperiod: 8\ngnssthreshold: 20.0\n");
  const PeerSetup s = loadPeerConfig(PeerFormat::kObGins, dir + "/ob.yaml");
  ASSERT_TRUE(s.outage_schedule);
  EXPECT_DOUBLE_EQ(s.outage_schedule->first_start_s, 110.0);  // below starttime: counted from it
  EXPECT_EQ(*s.window_nodes, 20);
  EXPECT_FALSE(s.initial_position);
  const ImportResult r = importPeerSetup(s, dir + "/case");
  ASSERT_EQ(r.outages.size(), 1u);  // 110-115; 118-123 ends after the last GNSS epoch (122)
  EXPECT_DOUBLE_EQ(r.outages[0].start_s, 110.0);
  const CaseConfig c = loadCaseConfig(dir + "/case/case.yaml");
  // The antenna is 1 m above the IMU: the IMU is 1 m below the first fix.
  EXPECT_NEAR(c.initial_state->pos.h_m, 19.0, 1e-6);
}

TEST(PeerImport, GnssGapsBecomeWindowsThatKeepTheBoundingFixes) {
  GnssSeries g;
  for (double t : {0.0, 1.0, 2.0, 3.0, 5.0, 6.0, 30.0, 31.0, 32.0}) {
    GnssFix f;
    f.t_s = t;
    g.push_back(f);
  }
  const auto w = gnssGapWindows(g, 0.0, 100.0, ImportOptions{});
  ASSERT_EQ(w.size(), 1u);  // the 2 s gap is below min_gap_s = 3 s
  EXPECT_GT(w[0].start_s, 6.0);
  EXPECT_LT(w[0].end_s, 30.0);
  EXPECT_NEAR(w[0].length_s(), 24.0, 0.01);
  EXPECT_TRUE(
      gnssGapWindows(g, 7.0, 100.0, ImportOptions{}).empty());  // gap starts before the range
  ImportOptions bad;
  bad.min_gap_s = 0.0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(PeerImport, KfGinsCaseLoadsBackWithItsRunConfig) {
  const std::string dir = test::makeTempDir("peer_case");
  writeData(dir);
  writeText(dir + "/kf.yaml", kKfGins);
  const PeerSetup s = loadPeerConfig(PeerFormat::kKfGins, dir + "/kf.yaml");
  const ImportResult r = importPeerSetup(s, dir + "/case");
  ASSERT_EQ(r.outages.size(), 1u);  // 103 .. 120
  const CaseConfig c = loadCaseConfig(dir + "/case/case.yaml");
  EXPECT_DOUBLE_EQ(c.imu_rate_hz, 100.0);
  EXPECT_NEAR(c.reference_imu->accel_bias_instability_m_s2, 500e-5, 1e-12);
  EXPECT_NEAR(c.initial_state->v_n.y(), 2.0, 1e-12);
  EXPECT_TRUE(std::filesystem::is_symlink(dir + "/case/field/ref_imu.txt"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/case/source/kf.yaml"));
  std::ifstream run(dir + "/case/run.yaml");
  std::stringstream ss;
  ss << run.rdbuf();
  EXPECT_THAT(ss.str(), HasSubstr("init_pos_std_m: 0.3"));
  EXPECT_THAT(ss.str(), HasSubstr("103.001"));
}

// OB_GINS's odometer: column 8 of its IMU file (or the mean of 8 and 9) becomes
// field/odometer.txt, never a temperature; the keys become run.yaml's odometer section with SI
// conversions noted, and no odometer or mounting key is left "NOT CONVERTED".
std::string obGinsOdometer(int imudatalen, bool use_odometer) {
  return "imufile: imu.txt\ngnssfile: gnss.pos\nwindows: 20\nstarttime: 100\nendtime: 0\n"
         "initvel: [0, 0, 0]\ninitatt: [0, 0, 90]\nimudatalen: " +
         std::to_string(imudatalen) +
         "\nimudatarate: 100\nisearth: true\nantlever: [0, 0, -1.0]\n"
         "odolever: [-0.5, 0.2, 0.8]\nbodyangle: [0, -0.30, 1.5]\n"
         "odometer: {isuseodo: " +
         std::string(use_odometer ? "true" : "false") +
         ", std: [0.05, 0.1, 0.2], srw: 100}\n"
         "imumodel: {arw: 0.24, vrw: 0.24, gbstd: 50.0, abstd: 250.0, corrtime: 1.0}\n";
}

TEST(PeerImport, ObGinsOdometerColumnAndKeysAreConverted) {
  const std::string dir = test::makeTempDir("peer_odo");
  writeData(dir);
  writeText(dir + "/imu.txt", "100.01 0 0 0 0 0 -0.098 1.50\n100.02 0 0 0 0 0 -0.098 1.70\n");
  writeText(dir + "/ob.yaml", obGinsOdometer(8, true));
  const PeerSetup s = loadPeerConfig(PeerFormat::kObGins, dir + "/ob.yaml");
  ASSERT_TRUE(s.odometer);
  EXPECT_TRUE(s.odometer->enabled);
  EXPECT_EQ(s.odometer_columns, 1);
  EXPECT_NEAR(*s.odometer->scale_random_walk_per_sqrt_s, 100e-6, 1e-15);
  // OB_GINS's std is a density (m/s/sqrt(Hz)): one 10 Hz update's sigma is std * sqrt(10).
  EXPECT_NEAR(s.odometer->rate_hz, 10.0, 0.0);
  EXPECT_NEAR(s.odometer->std_m_s.x(), 0.05 * std::sqrt(10.0), 1e-12);
  EXPECT_NEAR(s.odometer->std_m_s.z(), 0.2 * std::sqrt(10.0), 1e-12);
  EXPECT_NEAR(s.odometer->mounting_rad.z(), 1.5 * kDeg, 1e-12);
  for (const std::string& n : s.notes) EXPECT_THAT(n, ::testing::Not(HasSubstr("NOT CONVERTED")));
  importPeerSetup(s, dir + "/case");
  const OdometerSeries odo = readOdometer(dir + "/case/field/odometer.txt");
  ASSERT_EQ(odo.size(), 2u);
  EXPECT_NEAR(odo[0].t_s, 100.005, 1e-9);  // the mean over the sample, at its middle
  EXPECT_NEAR(odo[1].speed_m_s, 1.70, 1e-9);
  ImuReadOptions io;
  io.nominal_rate_hz = 100.0;
  for (const ImuSample& x : readImu(dir + "/case/field/ref_imu.txt", io))
    EXPECT_FALSE(x.hasTemperature());  // 7 columns: column 8 is no temperature
  std::ifstream run(dir + "/case/run.yaml");
  std::stringstream ss;
  ss << run.rdbuf();
  EXPECT_THAT(ss.str(), HasSubstr("odometer:"));
  EXPECT_THAT(ss.str(), HasSubstr("enabled: true"));
  EXPECT_THAT(ss.str(), HasSubstr("scale_random_walk_ppm_sqrt_s: 100"));
  EXPECT_THAT(ss.str(), HasSubstr("rate_hz: 10"));
  EXPECT_THAT(ss.str(), HasSubstr("mounting_deg: [0, -0.3"));
  EXPECT_THAT(ss.str(), HasSubstr("lever_arm_m: [-0.5, 0.2, 0.8]"));
}

TEST(PeerImport, ObGinsTwoWheelColumnsAreAveragedAndAMissingColumnIsAnError) {
  const std::string dir = test::makeTempDir("peer_odo2");
  writeData(dir);
  writeText(dir + "/imu.txt", "100.01 0 0 0 0 0 -0.098 1.0 2.0\n100.02 0 0 0 0 0 -0.098 3.0\n");
  writeText(dir + "/ob.yaml", obGinsOdometer(9, true));
  const PeerSetup s = loadPeerConfig(PeerFormat::kObGins, dir + "/ob.yaml");
  EXPECT_EQ(s.odometer_columns, 2);
  try {
    importPeerSetup(s, dir + "/case");
    FAIL() << "a line without the 9th column was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("imu.txt:2:"));
  }
  writeText(dir + "/imu.txt", "100.01 0 0 0 0 0 -0.098 1.0 2.0\n100.02 0 0 0 0 0 -0.098 3.0 5.0\n");
  importPeerSetup(s, dir + "/case");
  const OdometerSeries odo = readOdometer(dir + "/case/field/odometer.txt");
  EXPECT_NEAR(odo[0].speed_m_s, 1.5, 1e-9);
  EXPECT_NEAR(odo[1].speed_m_s, 4.0, 1e-9);
  // The odometer on with a 7-column IMU file: refused, naming the key.
  writeText(dir + "/ob7.yaml", obGinsOdometer(7, true));
  try {
    loadPeerConfig(PeerFormat::kObGins, dir + "/ob7.yaml");
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("odometer.isuseodo"));
  }
}

}  // namespace
}  // namespace graftnav
