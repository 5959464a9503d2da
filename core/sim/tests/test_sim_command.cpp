// `graftnav simulate` end to end on a tiny config, and the sim config parser's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "graftnav/io/case_config.h"
#include "graftnav/nav/earth.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sim/sim_config.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

std::string tinyConfig(const std::string& dir) {
  const std::string imu = test::sourceDir() + "/configs/imu/";
  std::ofstream f(dir + "/tiny.yaml");
  f << "name: tiny\nseed: 3\ngnss_week: 2200\nimu_rate_hz: 100\ntruth_rate_hz: 10\n"
    << "trajectory:\n  script:\n    start_time_s: 200000\n"
    << "    start_position: [30.5, 114.3, 20]\n    initial_yaw_deg: 45\n    segments:\n"
    << "      - {type: static, duration_s: 3}\n"
    << "      - {type: accelerate, to_speed_m_s: 8, duration_s: 6}\n"
    << "      - {type: figure_eight, radius_m: 25, laps: 1}\n"
    << "      - {type: stop, duration_s: 6}\n"
    << "reference_imu: {profile: " << imu << "pos830_navigation.yaml}\n"
    << "tested_imu:\n  profile: " << imu << "pos1100_mems.yaml\n"
    << "  gyro_bias_deg_h: [10, -5, 3]\n  gyro_nonorthogonality_urad: [100, 0, 0, 0, 0, -50]\n"
    << "gnss: {rate_hz: 1, noise_std_neu_m: [0.02, 0.02, 0.05], lever_arm_m: [0.2, 0, -1.0]}\n"
    << "lab:\n  static_duration_s: 20\n  six_position_duration_s: 2\n  rate_table_deg_s: [90]\n"
    << "  tilt_duration_s: 1\n  tilts: {tilt_a: [5, 0, 0]}\n";
  return dir + "/tiny.yaml";
}

int run(const std::string& args, const std::string& log) {
  return std::system((test::graftnavBinary() + " " + args + " > " + log + " 2>&1").c_str());
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(SimCommand, IdealCaseRoundTripsThroughFiles) {
  const std::string dir = test::makeTempDir("sim_cmd");
  const std::string cfg = tinyConfig(dir);
  const std::string out = dir + "/case";
  ASSERT_EQ(run("simulate --config " + cfg + " --out " + out + " --ideal", dir + "/log.txt"), 0)
      << slurp(dir + "/log.txt");
  const CasePaths paths(out);
  const CaseConfig cc = loadCaseConfig(paths.caseYaml());
  EXPECT_EQ(cc.name, "tiny");
  EXPECT_EQ(cc.imu_rate_hz, 100.0);
  ASSERT_TRUE(cc.lever_arm_m.has_value());
  EXPECT_NEAR(cc.lever_arm_m->x(), 0.2, 1e-12);
  ASSERT_TRUE(cc.lab.has_value());
  EXPECT_EQ(cc.lab->six_position_euler_rad.size(), 6u);

  const ImuSeries ref = readImu(paths.refImu(), {100.0, {}});
  const ImuSeries tested = readImu(paths.testedImu(), {100.0, {}});
  const NavSeries truth = readNav(paths.truthNav());
  const GnssSeries gnss = readGnssPos(paths.gnssPos());
  ASSERT_EQ(ref.size(), tested.size());
  // Ideal: the tested IMU equals the reference exactly.
  for (std::size_t k = 0; k < ref.size(); k += 97) {
    EXPECT_EQ(ref[k].dtheta_rad, tested[k].dtheta_rad);
    EXPECT_EQ(ref[k].dvel_m_s, tested[k].dvel_m_s);
  }
  EXPECT_EQ(truth.front().gnss_week, 2200);
  EXPECT_NEAR(truth.back().t_s - truth.front().t_s, ref.size() / 100.0, 1e-6);
  EXPECT_EQ(truth.size(), ref.size() / 10 + 1);
  EXPECT_EQ(
      gnss.size(),
      static_cast<std::size_t>(std::floor(truth.back().t_s) - std::ceil(truth.front().t_s)) + 1);
  // The initial state of case.yaml is the first truth epoch.
  ASSERT_TRUE(cc.initial_state.has_value());
  EXPECT_NEAR(cc.initial_state->pos.lat_rad, truth.front().pos.lat_rad, 1e-12);
  // Mechanizing the file's increments from the initial state reproduces the truth file.
  Strapdown sd(truth.front());
  for (const auto& s : ref) sd.step(s);
  const Eigen::Vector3d d = earth::nedFromGeodetic(truth.back().pos, sd.state().pos);
  EXPECT_LT(d.norm(), 2e-3);
  EXPECT_LT(rotationVectorFromQuat(truth.back().q_nb.conjugate() * sd.state().q_nb).norm(), 1e-7);
  // Lab files in the layout.
  EXPECT_TRUE(fs::exists(paths.labStatic()));
  for (int a = 0; a < 3; ++a) {
    EXPECT_TRUE(fs::exists(paths.sixPosition(a, true)));
    EXPECT_TRUE(fs::exists(paths.sixPosition(a, false)));
  }
  EXPECT_EQ(paths.rateFiles().size(), 6u);
  EXPECT_TRUE(fs::exists(paths.tilt("tilt_a")));
  EXPECT_EQ(readImu(paths.labStatic(), {100.0, {}}).size(), 2000u);
}

TEST(SimCommand, SeedMakesRunsReproducible) {
  const std::string dir = test::makeTempDir("sim_seed");
  const std::string cfg = tinyConfig(dir);
  for (const char* c : {"a", "b", "c"}) {
    const std::string seed = std::string(c) == "c" ? "6" : "5";
    ASSERT_EQ(run("simulate --config " + cfg + " --out " + dir + "/" + c + " --seed " + seed,
                  dir + "/log.txt"),
              0)
        << slurp(dir + "/log.txt");
  }
  const std::string a = slurp(dir + "/a/field/tested_imu.txt");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, slurp(dir + "/b/field/tested_imu.txt"));
  EXPECT_NE(a, slurp(dir + "/c/field/tested_imu.txt"));
  EXPECT_EQ(slurp(dir + "/a/lab/static.txt"), slurp(dir + "/b/lab/static.txt"));
  EXPECT_NE(slurp(dir + "/a/field/gnss.pos"), slurp(dir + "/c/field/gnss.pos"));
  // The tested IMU carries errors: its static gyro mean is off the ideal Earth rate by about the
  // configured bias (10, -5, 3 deg/h) plus the MEMS draws and noise (bounded generously).
  const ImuSeries st = readImu(dir + "/a/lab/static.txt", {100.0, {}});
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const auto& s : st) m += s.dtheta_rad / s.dt_s;
  m /= st.size();
  const CaseConfig cc = loadCaseConfig(dir + "/a/case.yaml");
  const Geodetic site{cc.lab->latitude_rad, 0.0, cc.lab->height_m};
  const Eigen::Vector3d ideal = earth::omega_ie_n(site.lat_rad);  // static attitude 0 0 0
  const double dev_deg_h = (m - ideal).norm() * kRadToDeg * 3600.0;
  EXPECT_GT(dev_deg_h, 1.0);
  EXPECT_LT(dev_deg_h, 200.0);
}

// Common random numbers: the lab static record carries the field tested IMU's noise stream, so
// lab noise sample k is field noise sample k (correlation ~1; ~0 without the flag). The tiny
// config's 20-s static record is shorter than its field test and is extended to cover it.
TEST(SimCommand, CommonRandomNumbersShareTheFieldNoiseWithTheLab) {
  const std::string dir = test::makeTempDir("sim_crn");
  std::string cfg = tinyConfig(dir);
  {
    // No static record: refused with the key named.
    std::string text = slurp(cfg);
    text.replace(text.find("static_duration_s: 20"), 21, "static_duration_s: 0");
    std::ofstream(dir + "/nostatic.yaml") << text;
  }
  ASSERT_NE(run("simulate --config " + dir + "/nostatic.yaml --out " + dir +
                    "/nostatic --common-random-numbers",
                dir + "/nostatic.txt"),
            0);
  EXPECT_NE(slurp(dir + "/nostatic.txt").find("lab.common_random_numbers"), std::string::npos)
      << slurp(dir + "/nostatic.txt");
  for (const char* c : {"ideal", "crn", "indep"}) {
    const std::string flag = std::string(c) == "ideal" ? " --ideal --common-random-numbers"
                             : std::string(c) == "crn" ? " --common-random-numbers"
                                                       : "";
    ASSERT_EQ(run("simulate --config " + cfg + " --out " + dir + "/" + c + flag, dir + "/log.txt"),
              0)
        << slurp(dir + "/log.txt");
  }
  const ImuSeries field_ideal = readImu(dir + "/ideal/field/tested_imu.txt", {100.0, {}});
  const ImuSeries lab_ideal = readImu(dir + "/ideal/lab/static.txt", {100.0, {}});
  auto correlation = [&](const std::string& c) {
    const ImuSeries field = readImu(dir + "/" + c + "/field/tested_imu.txt", {100.0, {}});
    const ImuSeries lab = readImu(dir + "/" + c + "/lab/static.txt", {100.0, {}});
    // Accelerometer x noise: first differences remove the constant bias and most of the motion.
    std::vector<double> a, b;
    const std::size_t n = std::min({field.size(), lab.size(), lab_ideal.size()});
    EXPECT_GT(n, 1500u);
    for (std::size_t k = 1; k < n; ++k) {
      const double nf = (field[k].dvel_m_s.x() - field_ideal[k].dvel_m_s.x()) -
                        (field[k - 1].dvel_m_s.x() - field_ideal[k - 1].dvel_m_s.x());
      const double nl = (lab[k].dvel_m_s.x() - lab_ideal[k].dvel_m_s.x()) -
                        (lab[k - 1].dvel_m_s.x() - lab_ideal[k - 1].dvel_m_s.x());
      a.push_back(nf);
      b.push_back(nl);
    }
    double ab = 0, aa = 0, bb = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      ab += a[k] * b[k];
      aa += a[k] * a[k];
      bb += b[k] * b[k];
    }
    return ab / std::sqrt(aa * bb);
  };
  EXPECT_GE(readImu(dir + "/crn/lab/static.txt", {100.0, {}}).size(), field_ideal.size());
  EXPECT_GT(correlation("crn"), 0.99);
  EXPECT_LT(std::abs(correlation("indep")), 0.1);
}

// A temperature section gives the tested IMU files a temperature column, and a bias temperature
// coefficient shows up as the configured bias change between the cold and the warm end.
TEST(SimCommand, TemperatureWarmUpAndBiasCoefficient) {
  const std::string dir = test::makeTempDir("sim_temp");
  std::string text = slurp(tinyConfig(dir));
  text.replace(text.find("  gyro_bias_deg_h"), 0,
               "  gyro_bias_per_degC_deg_h: [0, 0, 50]\n  temperature_ref_degC: 30\n");
  text += "temperature: {start_degC: 20, end_degC: 40, time_constant_s: 5}\n";
  { std::ofstream(dir + "/temp.yaml") << text; }
  ASSERT_EQ(run("simulate --config " + dir + "/temp.yaml --out " + dir + "/case", dir + "/log.txt"),
            0)
      << slurp(dir + "/log.txt");
  const ImuSeries st = readImu(dir + "/case/lab/static.txt", {100.0, {}});
  ASSERT_TRUE(st.front().hasTemperature());
  EXPECT_NEAR(st.front().temperature_degC, 20.0, 0.1);
  EXPECT_NEAR(st.back().temperature_degC, 40.0 - 20.0 * std::exp(-4.0), 0.1);
  EXPECT_FALSE(readImu(dir + "/case/field/ref_imu.txt", {100.0, {}}).front().hasTemperature());
  EXPECT_TRUE(readImu(dir + "/case/field/tested_imu.txt", {100.0, {}}).front().hasTemperature());
  auto mean = [&](std::size_t a, std::size_t b, double& temp) {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    temp = 0.0;
    for (std::size_t k = a; k < b; ++k) {
      m += st[k].dtheta_rad / st[k].dt_s;
      temp += st[k].temperature_degC;
    }
    temp /= (b - a);
    return Eigen::Vector3d(m / (b - a));
  };
  double t_cold = 0.0, t_warm = 0.0;
  const Eigen::Vector3d cold = mean(0, 200, t_cold);
  const Eigen::Vector3d warm = mean(st.size() - 200, st.size(), t_warm);
  const double expected = 50.0 * (t_warm - t_cold);  // deg/h
  // MEMS noise on two 2-s means: ~9 deg/h; the expected change is ~800 deg/h.
  EXPECT_NEAR((warm.z() - cold.z()) * kRadToDeg * 3600.0, expected, 0.05 * expected);
}

// A tested IMU with late tags measured the motion at t - tau, road vibration included: with the
// same seed, the file with tau = half a sample minus the file without it is the scaled
// difference of the ideal increments over the shifted and unshifted intervals (from an ideal
// 200-Hz run of the same drive). The error model's interpolating shift, used for the field file
// until this test, lost ~10 % of the 8-40 Hz vibration and so looked like a scale factor.
TEST(SimCommand, TimeOffsetShiftsTheMeasuredMotionExactly) {
  const std::string dir = test::makeTempDir("sim_tau");
  const std::string imu = test::sourceDir() + "/configs/imu/";
  const auto config = [&](const std::string& name, double rate_hz, double tau_s) {
    std::ofstream f(dir + "/" + name + ".yaml");
    f << "name: " << name << "\nseed: 11\ngnss_week: 2100\nimu_rate_hz: " << rate_hz
      << "\nquadrature_nodes: 4\ntruth_rate_hz: 10\ntrajectory:\n  track: " << test::sharedDir()
      << "/data/tracks/wuhan_27min_rtk.pos\n  start_offset_s: 300\n  duration_s: 40\n"
      << "  vibration: {accel_rms_m_s2: 0.6, gyro_rms_deg_s: 1.0, band_hz: [8, 40], components: 12, "
         "seed: 1, half_amplitude_speed_m_s: 5}\n"
      << "reference_imu: {profile: " << imu << "pos830_navigation.yaml}\n"
      << "tested_imu:\n  profile: " << imu << "pos1100_mems.yaml\n"
      << (tau_s != 0.0 ? "  time_offset_s: " + std::to_string(tau_s) + "\n" : "")
      << "gnss: {rate_hz: 1, noise_std_neu_m: [0.02, 0.02, 0.05], lever_arm_m: [0, 0, 0]}\n"
      << "lab:\n  static_duration_s: 2\n  six_position_duration_s: 1\n  rate_table_deg_s: [90]\n"
      << "  tilt_duration_s: 1\n  tilts: {tilt_a: [5, 0, 0]}\n";
    return dir + "/" + name + ".yaml";
  };
  const auto simulate = [&](const std::string& cfg, const std::string& out,
                            const std::string& extra) {
    ASSERT_EQ(run("simulate --config " + cfg + " --out " + out + extra, dir + "/log.txt"), 0)
        << slurp(dir + "/log.txt");
  };
  simulate(config("shifted", 100.0, 0.005), dir + "/shifted", "");
  simulate(config("unshifted", 100.0, 0.0), dir + "/unshifted", "");
  simulate(config("fine", 200.0, 0.0), dir + "/fine", " --ideal");
  const ImuSeries a = readImu(dir + "/shifted/field/tested_imu.txt", {100.0, {}});
  const ImuSeries b = readImu(dir + "/unshifted/field/tested_imu.txt", {100.0, {}});
  const ImuSeries c = readImu(dir + "/fine/field/ref_imu.txt", {200.0, {}});
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(c.size(), 2 * a.size());
  double err2 = 0.0, sig2 = 0.0;
  for (std::size_t k = 1; k < a.size(); ++k) {
    // Sample k covers (k, k+1] / 100 s after the start, shifted: 200-Hz samples 2k-1 and 2k.
    const Eigen::Vector3d expected =
        (c[2 * k - 1].dvel_m_s + c[2 * k].dvel_m_s) - (c[2 * k].dvel_m_s + c[2 * k + 1].dvel_m_s);
    const Eigen::Vector3d got = a[k].dvel_m_s - b[k].dvel_m_s;
    err2 += (got - expected).squaredNorm();
    sig2 += expected.squaredNorm();
  }
  // The sensor's scale factor and non-orthogonality (~1e-3) scale the difference too.
  EXPECT_LT(std::sqrt(err2 / sig2), 0.01) << "rms of the difference " << std::sqrt(sig2 / a.size());
}

// temperature.lab_degC: the lab files sit at a constant temperature while the field file still
// warms up.
TEST(SimCommand, LabTemperatureCanBeHeldConstant) {
  const std::string dir = test::makeTempDir("sim_lab_temp");
  std::string text = slurp(tinyConfig(dir));
  text += "temperature: {start_degC: 20, end_degC: 40, time_constant_s: 5, lab_degC: 23}\n";
  { std::ofstream(dir + "/temp.yaml") << text; }
  ASSERT_EQ(run("simulate --config " + dir + "/temp.yaml --out " + dir + "/case", dir + "/log.txt"),
            0)
      << slurp(dir + "/log.txt");
  for (const char* f : {"/case/lab/static.txt", "/case/lab/tilt/tilt_a.txt"}) {
    const ImuSeries lab = readImu(dir + f, {100.0, {}});
    ASSERT_TRUE(lab.front().hasTemperature()) << f;
    EXPECT_DOUBLE_EQ(lab.front().temperature_degC, 23.0) << f;
    EXPECT_DOUBLE_EQ(lab.back().temperature_degC, 23.0) << f;
  }
  const ImuSeries field = readImu(dir + "/case/field/tested_imu.txt", {100.0, {}});
  EXPECT_NEAR(field.front().temperature_degC, 20.0, 0.1);
  EXPECT_GT(field.back().temperature_degC, 39.0);
}

TEST(SimCommand, ConfigErrorsNameFileAndKey) {
  const std::string dir = test::makeTempDir("sim_cfg");
  const std::string cfg = tinyConfig(dir);
  std::string text = slurp(cfg);
  // Break the first segment's type.
  text.replace(text.find("type: static"), 12, "type: hover");
  { std::ofstream(dir + "/bad.yaml") << text; }
  try {
    loadSimConfig(dir + "/bad.yaml");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bad.yaml:"), std::string::npos) << m;
    EXPECT_NE(m.find("segments[0].type"), std::string::npos) << m;
    EXPECT_NE(m.find("hover"), std::string::npos) << m;
  }
  std::vector<std::string> warnings;
  { std::ofstream(dir + "/extra.yaml") << slurp(cfg) << "colour: blue\n"; }
  const SimConfig c = loadSimConfig(dir + "/extra.yaml", &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("colour"), std::string::npos);
  EXPECT_NEAR(c.tested_imu.extra.gyro.constant_bias.b.x(), 10.0 * kDegToRad / 3600.0, 1e-15);
  EXPECT_NEAR(c.tested_imu.extra.gyro.non_orthogonality.N(0, 1), 100e-6, 1e-18);
  EXPECT_NEAR(c.tested_imu.extra.gyro.non_orthogonality.N(2, 1), -50e-6, 1e-18);
  // The command reports a missing section and exits non-zero.
  { std::ofstream(dir + "/notrj.yaml") << "name: x\nreference_imu: {profile: a.yaml}\n"; }
  EXPECT_NE(run("simulate --config " + dir + "/notrj.yaml --out " + dir + "/o", dir + "/log.txt"),
            0);
  EXPECT_NE(slurp(dir + "/log.txt").find("trajectory"), std::string::npos)
      << slurp(dir + "/log.txt");
}

}  // namespace
}  // namespace graftnav
