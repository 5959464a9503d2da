// `graftnav import kf-gins` then `graftnav navigate` on a KF-GINS-style set-up made from the
// bundled MEMS sample (written by `graftnav simulate`, scripts/dev/make_sample.sh): the tested IMU's
// file, the GNSS file with two 60 s stretches deleted (how a KF-GINS user makes outages), and a
// kf-gins.yaml with the sample's noise in KF-GINS units. The imported run's outage horizontal
// error must be within 2 % of the same estimator set up by hand on the original case (explicit
// outage windows, same initial sigmas, gate off): the set-up a user needed four tries for, and
// which matched KF-GINS's own number on a real drive.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fmt/core.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "graftnav/io/case_config.h"
#include "graftnav/nav/rotation.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}

int run(const std::string& args, const std::string& log) {
  const std::string cmd = test::graftnavBinary() + " " + args + " > " + log + " 2>&1";
  return std::system(cmd.c_str());
}

double outageHorizontalRms(const std::string& errors_json) {
  const auto j = nlohmann::json::parse(readAll(errors_json));
  return j.at("outage").at("horizontal_m").get<double>();
}

// Copies the GNSS file without the epochs strictly inside the two outage windows.
void writeGnssWithGaps(const std::string& from, const std::string& to) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  while (std::getline(in, line)) {
    const double t = std::stod(line);
    const bool in_gap = (t > 456460.0 && t < 456520.0) || (t > 456600.0 && t < 456660.0);
    if (!in_gap) out << line << '\n';
  }
}

std::string kfGinsYaml(const CaseConfig& c) {
  const NavState& x = *c.initial_state;
  const Eigen::Vector3d e = eulerFromQuat(x.q_nb) * kRadToDeg;
  const ImuProfile& p = *c.tested_imu;
  const double arw = p.arw_rad_sqrt_s * kRadToDeg * 60.0, vrw = p.vrw_m_s_sqrt_s * 60.0;
  const double gb = p.gyro_bias_instability_rad_s * kRadToDeg * 3600.0,
               ab = p.accel_bias_instability_m_s2 * 1e5;
  std::ostringstream y;
  y.precision(15);
  y << "imupath: \"imu.txt\"\ngnsspath: \"gnss.txt\"\noutputpath: \"./out\"\nimudatalen: 7\n"
    << "imudatarate: " << c.testedImuRateHz() << "\nstarttime: " << x.t_s << "\nendtime: -1\n"
    << "initpos: [" << x.pos.lat_rad * kRadToDeg << ", " << x.pos.lon_rad * kRadToDeg << ", "
    << x.pos.h_m << "]\n"
    << "initvel: [" << x.v_n.x() << ", " << x.v_n.y() << ", " << x.v_n.z() << "]\n"
    << "initatt: [" << e.x() << ", " << e.y() << ", " << e.z() << "]\n"
    << "initgyrbias: [0, 0, 0]\ninitaccbias: [0, 0, 0]\ninitgyrscale: [0, 0, 0]\ninitaccscale: [0, 0, 0]\n"
    << "initposstd: [0.5, 0.5, 0.5]\ninitvelstd: [0.1, 0.1, 0.1]\ninitattstd: [0.1, 0.1, 0.5]\n"
    << "imunoise:\n  arw: [" << arw << ", " << arw << ", " << arw << "]\n  vrw: [" << vrw << ", "
    << vrw << ", " << vrw << "]\n  gbstd: [" << gb << ", " << gb << ", " << gb << "]\n  abstd: ["
    << ab << ", " << ab << ", " << ab << "]\n  gsstd: [" << p.gyro_scale_std * 1e6 << ", "
    << p.gyro_scale_std * 1e6 << ", " << p.gyro_scale_std * 1e6 << "]\n  asstd: ["
    << p.accel_scale_std * 1e6 << ", " << p.accel_scale_std * 1e6 << ", " << p.accel_scale_std * 1e6
    << "]\n  corrtime: " << p.gyro_bias_corr_time_s / 3600.0 << "\n"
    << "antlever: [" << c.lever_arm_m->x() << ", " << c.lever_arm_m->y() << ", "
    << c.lever_arm_m->z() << "]\n";
  return y.str();
}

TEST(ImportApp, KfGinsSetupNavigatesWithinTwoPercentOfTheHandSetup) {
  const std::string sample = test::sourceDir() + "/data/sample_mems";
  const std::string dir = test::makeTempDir("import_kf_gins");
  const CaseConfig c = loadCaseConfig(sample + "/case.yaml");
  ASSERT_TRUE(c.initial_state && c.tested_imu && c.lever_arm_m);
  fs::copy_file(sample + "/field/tested_imu.txt", dir + "/imu.txt");
  fs::copy_file(sample + "/field/truth.nav", dir + "/truth.nav");
  writeGnssWithGaps(sample + "/field/gnss.pos", dir + "/gnss.txt");
  writeText(dir + "/kf-gins.yaml", kfGinsYaml(c));
  writeText(dir + "/hand.yaml",
            "outages:\n  windows: [[456460.001, 456519.999], [456600.001, 456659.999]]\n"
            "ekf:\n  gate_probability: 0\n  init_pos_std_m: 0.5\n  init_vel_std_m_s: 0.1\n"
            "  init_roll_pitch_std_deg: 0.1\n  init_heading_std_deg: 0.5\n");

  ASSERT_EQ(run("import kf-gins " + dir + "/kf-gins.yaml --out " + dir + "/case --reference " +
                    dir + "/truth.nav",
                dir + "/import.log"),
            0)
      << readAll(dir + "/import.log");
  const std::string import_log = readAll(dir + "/import.log");
  EXPECT_THAT(import_log, ::testing::HasSubstr("2 outage windows"));
  EXPECT_THAT(readAll(dir + "/case/notes.md"),
              ::testing::HasSubstr("outage windows from GNSS gaps"));
  ASSERT_EQ(run("navigate " + dir + "/case --out " + dir + "/imported --no-plots",
                dir + "/nav_imported.log"),
            0)
      << readAll(dir + "/nav_imported.log");
  ASSERT_EQ(run("navigate " + sample + " --imu tested --run-config " + dir + "/hand.yaml --out " +
                    dir + "/hand --no-plots",
                dir + "/nav_hand.log"),
            0)
      << readAll(dir + "/nav_hand.log");

  const double imported = outageHorizontalRms(dir + "/imported/errors.json");
  const double hand = outageHorizontalRms(dir + "/hand/errors.json");
  ASSERT_GT(hand, 0.5);  // a MEMS IMU drifts metres in 60 s: the comparison is not one of zeros
  EXPECT_NEAR(imported / hand, 1.0, 0.02) << "imported " << imported << " m, hand " << hand << " m";
  const auto info = nlohmann::json::parse(readAll(dir + "/imported/run_info.json"));
  EXPECT_EQ(info.at("outage_windows_s").size(), 2u);
  // Provenance: the command line and a hash of each config the run read (case.yaml, run.yaml).
  const auto& prov = info.at("provenance");
  EXPECT_EQ(prov.at("command_line").at(1), "navigate");
  EXPECT_THAT(prov.at("git_commit").get<std::string>(),
              ::testing::MatchesRegex("([0-9a-f]{12}(-dirty)?|unknown)"));
  ASSERT_EQ(prov.at("configs").size(), 2u);
  EXPECT_THAT(prov.at("configs")[1].at("path").get<std::string>(),
              ::testing::EndsWith("case/run.yaml"));
  EXPECT_EQ(prov.at("configs")[1].at("fnv1a64").get<std::string>().size(), 16u);
  // Per-epoch outputs in the i2Nav layouts, one row per solution epoch after the header.
  std::ifstream std_file(dir + "/imported/state_std.txt");
  std::string header;
  std::getline(std_file, header);
  EXPECT_EQ(header.rfind("# time_s pos_std_n_m", 0), 0u) << header;
}

// The odometer carried in column 8 of an OB_GINS IMU file: the IMU lines of `imu` with the speed
// of `odometer` (sampled at the IMU epochs) appended.
void writeImuWithOdometerColumn(const std::string& imu, const std::string& odometer,
                                const std::string& to) {
  std::ifstream odo_in(odometer);
  std::map<long, std::string> speed;  // by IMU epoch in ms
  for (double t, v; odo_in >> t >> v;) speed[std::lround(t * 1e3)] = fmt::format("{:.6f}", v);
  std::ifstream in(imu);
  std::ofstream out(to);
  std::string line;
  while (std::getline(in, line)) {
    const auto it = speed.find(std::lround(std::stod(line) * 1e3));
    if (it == speed.end()) continue;  // before the odometer's first sample
    std::istringstream cols(line);
    std::string c, seven;
    for (int i = 0; i < 7 && cols >> c; ++i) seven += (i ? " " : "") + c;
    out << seven << ' ' << it->second << '\n';
  }
}

// `import ob-gins` of a set-up of OB_GINS's dataset shape with the odometer on (the fixture
// tests/apps/data/ob_gins_odometer.yaml) over a generated 5-minute drive, then `navigate`: the
// run uses the odometer (updates counted, the scale estimated near the simulated 3000 ppm), and
// the outage error is far below the same case navigated with the odometer switched off.
TEST(ImportApp, ObGinsOdometerSetupNavigatesWithTheOdometer) {
  const std::string data = test::sourceDir() + "/tests/apps/data";
  const std::string dir = test::makeTempDir("import_ob_gins_odo");
  ASSERT_EQ(run("simulate --sim-config " + data + "/ob_gins_drive_sim.yaml --out " + dir + "/sim",
                dir + "/sim.log"),
            0)
      << readAll(dir + "/sim.log");
  writeImuWithOdometerColumn(dir + "/sim/field/tested_imu.txt", dir + "/sim/field/odometer.txt",
                             dir + "/imu.txt");
  fs::copy_file(dir + "/sim/field/gnss.pos", dir + "/gnss.txt");
  fs::copy_file(data + "/ob_gins_odometer.yaml", dir + "/ob_gins.yaml");
  ASSERT_EQ(run("import ob-gins " + dir + "/ob_gins.yaml --out " + dir + "/case --reference " +
                    dir + "/sim/field/truth.nav",
                dir + "/import.log"),
            0)
      << readAll(dir + "/import.log");
  EXPECT_THAT(readAll(dir + "/import.log"), ::testing::Not(::testing::HasSubstr("NOT CONVERTED")));
  ASSERT_TRUE(fs::exists(dir + "/case/field/odometer.txt"));
  const std::string run_yaml = readAll(dir + "/case/run.yaml");
  ASSERT_THAT(run_yaml, ::testing::HasSubstr("odometer:"));

  ASSERT_EQ(run("navigate " + dir + "/case --out " + dir + "/aided --no-plots", dir + "/aided.log"),
            0)
      << readAll(dir + "/aided.log");
  std::string off = run_yaml;
  off.replace(off.find("enabled: true"), 13, "enabled: false");
  writeText(dir + "/off.yaml", off);
  ASSERT_EQ(run("navigate " + dir + "/case --run-config " + dir + "/off.yaml --out " + dir +
                    "/free --no-plots",
                dir + "/free.log"),
            0)
      << readAll(dir + "/free.log");

  const auto info = nlohmann::json::parse(readAll(dir + "/aided/run_info.json"));
  ASSERT_TRUE(info.contains("vehicle_aiding")) << info.dump(1);
  EXPECT_GT(info["vehicle_aiding"]["used"].get<int>(), 1000);  // 10 Hz over ~5 min
  const double k_ppm = info["vehicle_aiding"]["odometer_scale_ppm"].get<double>();
  const double k_std = info["vehicle_aiding"]["odometer_scale_std_ppm"].get<double>();
  EXPECT_LT(std::abs(k_ppm - 3000.0), 3.0 * k_std) << k_ppm << " +- " << k_std << " ppm";
  EXPECT_TRUE(fs::exists(dir + "/aided/odometer_scale.txt"));
  EXPECT_FALSE(
      nlohmann::json::parse(readAll(dir + "/free/run_info.json")).contains("vehicle_aiding"));
  const double aided = outageHorizontalRms(dir + "/aided/errors.json");
  const double free = outageHorizontalRms(dir + "/free/errors.json");
  ASSERT_GT(free, 0.5);  // the MEMS IMU drifts metres in a 60 s outage without the odometer
  EXPECT_LT(aided, 0.3 * free) << "with the odometer " << aided << " m, without " << free << " m";
}

TEST(ImportApp, MissingDataFileNamesEveryPathTried) {
  const std::string dir = test::makeTempDir("import_missing");
  writeText(dir + "/kf.yaml",
            "imupath: nowhere.txt\ngnsspath: gnss.txt\nimudatarate: 200\nstarttime: 0\n"
            "initpos: [30, 114, 20]\ninitatt: [0, 0, 0]\n");
  EXPECT_NE(run("import kf-gins " + dir + "/kf.yaml --out " + dir + "/case", dir + "/log"), 0);
  const std::string log = readAll(dir + "/log");
  EXPECT_THAT(log, ::testing::HasSubstr("imupath"));
  EXPECT_THAT(log, ::testing::HasSubstr(dir + "/nowhere.txt"));
}

}  // namespace
}  // namespace graftnav
