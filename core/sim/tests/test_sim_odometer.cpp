// `graftnav simulate` with an odometer section: field/odometer.txt holds the truth's forward
// speed at the odometer read with the configured scale error, white noise and quantization, and
// simulation.yaml records what was injected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "graftnav/io/case_config.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/nav/nav_interp.h"
#include "test_support.h"

namespace graftnav {
namespace {

std::string config(const std::string& dir, const std::string& odometer) {
  const std::string imu = test::sourceDir() + "/configs/imu/";
  std::ofstream f(dir + "/odo.yaml");
  f << "name: odo\nseed: 4\ngnss_week: 2200\nimu_rate_hz: 100\ntruth_rate_hz: 100\n"
    << "trajectory:\n  script:\n    start_time_s: 200000\n"
    << "    start_position: [30.5, 114.3, 20]\n    initial_yaw_deg: 45\n    segments:\n"
    << "      - {type: static, duration_s: 3}\n"
    << "      - {type: accelerate, to_speed_m_s: 12, duration_s: 8}\n"
    << "      - {type: turn, rate_deg_s: 10, duration_s: 9}\n"
    << "      - {type: cruise, duration_s: 20}\n"
    << "reference_imu: {profile: " << imu << "pos830_navigation.yaml}\n"
    << "tested_imu: {profile: " << imu << "pos1100_mems.yaml}\n"
    << "gnss: {rate_hz: 1}\n"
    << "lab: {static_duration_s: 0, six_position_duration_s: 0, rate_table_deg_s: [], "
       "tilt_duration_s: 0}\n"
    << odometer;
  return dir + "/odo.yaml";
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

int simulate(const std::string& cfg, const std::string& out, const std::string& flags = "") {
  return std::system((test::graftnavBinary() + " simulate --config " + cfg + " --out " + out + " " +
                      flags + " > " + out + ".log 2>&1")
                         .c_str());
}

// Reading minus (1 + k) times the truth's horizontal speed (the scripted car rolls along its
// heading, pitch 0, odometer at the IMU), over the samples where the car moves.
struct Residual {
  double mean = 0.0, rms = 0.0;
  int moving = 0, at_rest_nonzero = 0;  // readings off the noise-free value at rest
};
Residual residual(const std::string& case_dir, double k) {
  const CasePaths paths(case_dir);
  const OdometerSeries odo = readOdometer(paths.odometer());
  const NavSeries truth = readNav(paths.truthNav());
  Residual r;
  double s = 0.0, s2 = 0.0;
  for (const OdometerSample& o : odo) {
    const auto st = interpolateNav(truth, o.t_s, 1e-3);
    if (!st) continue;
    const double v = st->v_n.head<2>().norm();
    const double d = o.speed_m_s - (1.0 + k) * v;
    if (v < 1e-3) {  // standing (or creeping below 1 mm/s): no noise on the reading
      r.at_rest_nonzero += std::abs(d) > 2e-6;
      continue;
    }
    s += d;
    s2 += d * d;
    ++r.moving;
  }
  r.mean = s / r.moving;
  r.rms = std::sqrt(s2 / r.moving);
  return r;
}

TEST(SimOdometer, IdealReadingsCarryExactlyTheScaleError) {
  const std::string dir = test::makeTempDir("sim_odo_ideal");
  const std::string cfg = config(dir, "odometer: {rate_hz: 20, scale_error_ppm: 3000}\n");
  ASSERT_EQ(simulate(cfg, dir + "/case", "--ideal"), 0) << slurp(dir + "/case.log");
  const OdometerSeries odo = readOdometer(CasePaths(dir + "/case").odometer());
  EXPECT_EQ(odo.size(), 801u);  // 40 s at 20 Hz, both ends
  const Residual r = residual(dir + "/case", 3000e-6);
  EXPECT_GT(r.moving, 700);
  EXPECT_LT(r.rms, 1e-5);  // the file's 6 decimals
  EXPECT_EQ(r.at_rest_nonzero, 0);
  EXPECT_GT(residual(dir + "/case", 0.0).mean, 0.02);  // 0.3 % of ~10 m/s
}

TEST(SimOdometer, NoiseAndQuantizationAsConfiguredAndRecorded) {
  const std::string dir = test::makeTempDir("sim_odo_noise");
  const std::string cfg =
      config(dir, "odometer: {rate_hz: 50, scale_error_ppm: -2000, noise_std_m_s: 0.05}\n");
  ASSERT_EQ(simulate(cfg, dir + "/case"), 0) << slurp(dir + "/case.log");
  const Residual r = residual(dir + "/case", -2000e-6);
  EXPECT_NEAR(r.rms, 0.05, 0.005);
  EXPECT_LT(std::abs(r.mean), 0.005);
  EXPECT_EQ(r.at_rest_nonzero, 0);  // a wheel at rest gives no pulse
  EXPECT_NE(slurp(dir + "/case/simulation.yaml").find("scale_error_ppm: -2000"), std::string::npos);

  const std::string qdir = test::makeTempDir("sim_odo_quant");
  const std::string qcfg =
      config(qdir, "odometer: {rate_hz: 10, noise_std_m_s: 0, quantization_m_s: 0.1}\n");
  ASSERT_EQ(simulate(qcfg, qdir + "/case"), 0) << slurp(qdir + "/case.log");
  for (const OdometerSample& o : readOdometer(CasePaths(qdir + "/case").odometer())) {
    EXPECT_NEAR(o.speed_m_s * 10.0, std::round(o.speed_m_s * 10.0), 1e-6) << o.t_s;
  }
}

TEST(SimOdometer, BadOdometerKeyNamesFileAndKey) {
  const std::string dir = test::makeTempDir("sim_odo_bad");
  const std::string cfg = config(dir, "odometer: {rate_hz: 0}\n");
  ASSERT_NE(simulate(cfg, dir + "/case"), 0);
  const std::string log = slurp(dir + "/case.log");
  EXPECT_NE(log.find("odo.yaml"), std::string::npos) << log;
  EXPECT_NE(log.find("odometer"), std::string::npos) << log;
  EXPECT_NE(log.find("rate_hz"), std::string::npos) << log;
}

}  // namespace
}  // namespace graftnav
