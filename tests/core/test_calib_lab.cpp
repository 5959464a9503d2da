// End-to-end lab calibration on simulated lab sessions (the project's lab simulator + error
// model, written to a case directory and read back) and on the real Ferraris session.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "graftnav/core/calibration/calibration_io.h"
#include "graftnav/core/calibration/lab_calibration.h"
#include "graftnav/core/case_config.h"
#include "graftnav/core/imu_error_model.h"
#include "graftnav/core/imu_io.h"
#include "graftnav/core/lab_simulator.h"
#include "graftnav/core/rotation.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

LabSimOptions labOptions(double static_s) {
  LabSimOptions o;
  o.rate_hz = 50.0;
  o.static_duration_s = static_s;
  o.six_position_duration_s = 30.0;
  o.rate_table_rad_s = {20 * kDegToRad, 50 * kDegToRad, 100 * kDegToRad, 200 * kDegToRad};
  o.tilt_duration_s = 30.0;
  o.tilt_euler_rad = {{"roll30", Eigen::Vector3d(30, 0, 0) * kDegToRad},
                      {"pitch45", Eigen::Vector3d(0, 45, 0) * kDegToRad},
                      {"roll120", Eigen::Vector3d(120, 0, 0) * kDegToRad},
                      {"pitchm60", Eigen::Vector3d(0, -60, 20) * kDegToRad}};
  return o;
}

// Injected deterministic errors drawn from the seed (tactical/MEMS-like magnitudes).
ImuErrorModel drawModel(unsigned seed, bool nonlinear) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  ImuErrorModel m;
  auto vec = [&](double s) -> Eigen::Vector3d { return Eigen::Vector3d(g(rng), g(rng), g(rng)) * s; };
  m.gyro.constant_bias.b = vec(50.0 * kDegToRad / 3600.0);
  m.gyro.scale_factor.k = vec(1e-3);
  m.accel.constant_bias.b = vec(0.02);
  m.accel.scale_factor.k = vec(1e-3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) {
        m.gyro.non_orthogonality.N(i, j) = 1e-3 * g(rng);
        m.accel.non_orthogonality.N(i, j) = 1e-3 * g(rng);
      }
  m.gyro.white_noise.density.setConstant(0.3 * kDegToRad / 60.0);  // 0.3 deg/sqrt(h)
  m.accel.white_noise.density.setConstant(0.05 / 60.0);             // 0.05 m/s/sqrt(h)
  if (nonlinear) {
    m.gyro.scale_nonlinearity.k2 = vec(2e-3);   // 1/(rad/s)
    m.accel.scale_nonlinearity.k2 = vec(1e-4);  // 1/(m/s^2)
  }
  return m;
}

// Writes a simulated case; the static record additionally gets `static_extra` (bias instability).
void writeSimCase(const std::string& dir, const LabSimOptions& o, const ImuErrorModel& model,
                  const ImuErrorModel& static_model, unsigned seed) {
  const auto sessions = simulateLabSessions(o);
  uint64_t stream = 0;
  for (const auto& s : sessions) {
    const std::string path = dir + "/" + s.relative_path;
    fs::create_directories(fs::path(path).parent_path());
    const bool is_static = s.relative_path == "lab/static.txt";
    writeImu(path, applyErrors(s.ideal, is_static ? static_model : model, seed * 1000 + (++stream)));
  }
  CaseConfig cfg;
  cfg.name = "sim_lab_" + std::to_string(seed);
  cfg.imu_rate_hz = o.rate_hz;
  LabConfig lab;
  lab.latitude_rad = o.latitude_rad;
  lab.height_m = o.height_m;
  lab.static_euler_rad = o.static_euler_rad;
  lab.rate_table_axis_up = true;
  lab.tilt_euler_rad = o.tilt_euler_rad;
  cfg.lab = lab;
  saveCaseConfig(dir + "/case.yaml", cfg);
}

struct Zscores {
  std::vector<double> z;
  void add(double est, double truth, double sigma) { z.push_back((est - truth) / sigma); }
  double maxAbs() const {
    double m = 0.0;
    for (double v : z) m = std::max(m, std::abs(v));
    return m;
  }
};

void checkLinear(const SensorCalibration& s, const SensorErrorTerms& t, Zscores& zs) {
  const Eigen::Matrix3d M = t.scaleMisalignmentMatrix();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) zs.add(s.M(i, j), M(i, j), s.M_sigma(i, j));
    zs.add(s.bias[i], t.constant_bias.b[i], s.bias_sigma[i]);
  }
}

TEST(CalibLab, SimulatedSessionRecoversInjectedParametersWithinThreeSigma) {
  for (unsigned seed : {101u, 102u}) {
    const std::string dir = test::makeTempDir("calib_lab_sim_" + std::to_string(seed));
    const ImuErrorModel model = drawModel(seed, false);
    writeSimCase(dir, labOptions(600.0), model, model, seed);
    const LabData data = loadLabData(dir);
    EXPECT_EQ(data.six_position.size(), 6u);
    EXPECT_EQ(data.tilts.size(), 4u);
    EXPECT_EQ(data.rate_runs.size(), 24u);
    const LabCalibrationReport rep = calibrateLab(data);
    Zscores za, zg;
    checkLinear(rep.result.accel, model.accel, za);
    checkLinear(rep.result.gyro, model.gyro, zg);
    EXPECT_LT(za.maxAbs(), 3.0) << "accel, seed " << seed;
    EXPECT_LT(zg.maxAbs(), 3.0) << "gyro, seed " << seed;
    // Uncertainties are those of the injected noise (not vacuous).
    EXPECT_LT(rep.result.gyro.M_sigma.maxCoeff(), 1e-4);
    EXPECT_LT(rep.result.accel.M_sigma.maxCoeff(), 1e-4);
    // Eq. 9 and Eq. 10-11 agree with the least squares.
    ASSERT_TRUE(rep.has_eq9 && rep.has_eq10);
    EXPECT_LT((rep.eq10.M - rep.result.gyro.M).cwiseAbs().maxCoeff(), 1e-4);
    // Calibrated |f| at rest is closer to gravity.
    EXPECT_LT(rep.norm_rms_after, 0.1 * rep.norm_rms_before);
    // Allan white noise of the 10-min static record.
    ASSERT_TRUE(rep.has_allan);
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(std::abs(rep.result.gyro.allan.white_noise[a] - model.gyro.white_noise.density[a]),
                3.0 * rep.result.gyro.allan.white_noise_sigma[a]);
      EXPECT_LT(std::abs(rep.result.accel.allan.white_noise[a] - model.accel.white_noise.density[a]),
                3.0 * rep.result.accel.allan.white_noise_sigma[a]);
    }
    // Round trip through calibration.yaml.
    writeCalibrationYaml(dir + "/calibration.yaml", rep.result);
    const CalibrationResult back = readCalibrationYaml(dir + "/calibration.yaml");
    EXPECT_LT((back.gyro.M - rep.result.gyro.M).cwiseAbs().maxCoeff(), 1e-11);
    fs::remove_all(dir);
  }
}

TEST(CalibLab, SimulatedNonlinearityRecoveredByTheFittingFunctions) {
  const unsigned seed = 201;
  const std::string dir = test::makeTempDir("calib_lab_fit");
  const ImuErrorModel model = drawModel(seed, true);
  writeSimCase(dir, labOptions(0.0), model, model, seed);
  const LabCalibrationReport rep = calibrateLab(loadLabData(dir));
  ASSERT_TRUE(rep.result.gyro.has_fit);
  ASSERT_TRUE(rep.result.accel.has_fit);
  for (const auto* sensor : {&rep.result.gyro, &rep.result.accel}) {
    const SensorErrorTerms& t = sensor == &rep.result.gyro ? model.gyro : model.accel;
    for (int a = 0; a < 3; ++a) {
      const PolynomialFit& f = sensor->fit[a];
      ASSERT_GE(f.degree, 2) << sensor->method << " axis " << a;
      const double truth[3] = {t.constant_bias.b[a], 1.0 + t.scale_factor.k[a], t.scale_nonlinearity.k2[a]};
      for (int k = 0; k < 3; ++k)
        EXPECT_LT(std::abs(f.coeffs[k] - truth[k]), 3.0 * f.coeffs_sigma[k])
            << sensor->method << " axis " << a << " c" << k << " = " << f.coeffs[k] << " vs " << truth[k];
    }
  }
  fs::remove_all(dir);
}

// ---- bad lab data: each is a clear error naming the file ----

class CalibLabBad : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::makeTempDir("calib_lab_bad");
    LabSimOptions o = labOptions(0.0);
    o.rate_table_rad_s = {50 * kDegToRad};
    o.tilt_euler_rad.clear();
    o.six_position_duration_s = 10.0;
    const ImuErrorModel m = drawModel(7, false);
    writeSimCase(dir, o, m, m, 7);
  }
  void TearDown() override { fs::remove_all(dir); }
  void expectError(const std::string& needle1, const std::string& needle2) {
    try {
      calibrateLab(loadLabData(dir));
      FAIL() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(needle1), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle2), std::string::npos) << e.what();
    }
  }
  std::string dir;
};

TEST_F(CalibLabBad, BaselineLoads) { EXPECT_NO_THROW(calibrateLab(loadLabData(dir))); }

TEST_F(CalibLabBad, MissingPose) {
  fs::remove(dir + "/lab/six_position/y_down.txt");
  expectError("y_down.txt", "missing six-position pose");
}

TEST_F(CalibLabBad, PoseNotStatic) {
  fs::copy_file(dir + "/lab/rate/z_pos_50.txt", dir + "/lab/six_position/z_up.txt",
                fs::copy_options::overwrite_existing);
  expectError("z_up.txt", "not static");
}

TEST_F(CalibLabBad, PoseAtTheWrongAttitude) {
  fs::copy_file(dir + "/lab/six_position/x_down.txt", dir + "/lab/six_position/x_up.txt",
                fs::copy_options::overwrite_existing);
  expectError("x_up.txt", "deg away from the attitude");
}

TEST_F(CalibLabBad, AttitudeThatContradictsThePoseName) {
  std::ofstream(dir + "/case.yaml", std::ios::app) << "";  // keep the file; rewrite the lab section
  CaseConfig cfg = loadCaseConfig(dir + "/case.yaml");
  cfg.lab->six_position_euler_rad["x_up"] = Eigen::Vector3d(0, -90, 0) * kDegToRad;
  saveCaseConfig(dir + "/case.yaml", cfg);
  expectError("x_up", "does not put the x axis up");
}

TEST_F(CalibLabBad, RateFileNotWholeTurns) {
  ImuSeries s = readImu(dir + "/lab/rate/x_neg_50.txt");
  s.resize(s.size() * 6 / 10);
  writeImu(dir + "/lab/rate/x_neg_50.txt", s);
  expectError("x_neg_50.txt", "not a whole number of turns");
}

TEST_F(CalibLabBad, NoLabData) {
  fs::remove_all(dir + "/lab");
  expectError(dir, "insufficient lab data");
}

// ---- real Ferraris session (shared/data/real/imucal_ferraris) ----
TEST(CalibLab, RealFerrarisSixPositionAndRotations) {
  const std::string dir = test::sharedDir() + "/data/real/imucal_ferraris";
  if (!fs::exists(dir + "/case.yaml")) GTEST_SKIP() << "real data not found: " << dir;
  const LabData data = loadLabData(dir);
  EXPECT_FALSE(data.latitude_known);  // 0/0 placeholders
  EXPECT_DOUBLE_EQ(data.gravity_m_s2, 9.80665);
  ASSERT_EQ(data.six_position.size(), 6u);
  ASSERT_EQ(data.rate_runs.size(), 3u);
  const LabCalibrationReport rep = calibrateLab(data);
  const SensorCalibration& a = rep.result.accel;
  const SensorCalibration& g = rep.result.gyro;
  EXPECT_GT(a.M_sigma.minCoeff(), 0.0);
  EXPECT_GT(g.M_sigma.minCoeff(), 0.0);
  // Accel scale errors of a few percent with tight uncertainty; calibrated |f| closer to g.
  EXPECT_LT(rep.norm_rms_after, 0.2 * rep.norm_rms_before);
  EXPECT_GT(rep.norm_rms_before, 0.3);
  // The hand rotations integrate to -371.9, -354.8, -359.2 deg uncalibrated (README), so the
  // gyro diagonal is near 1.033, 0.986, 0.998.
  EXPECT_NEAR(g.M(0, 0), 371.9 / 360.0, 0.01);
  EXPECT_NEAR(g.M(1, 1), 354.8 / 360.0, 0.01);
  EXPECT_NEAR(g.M(2, 2), 359.2 / 360.0, 0.01);
  std::printf("Ferraris: |f|-g RMS over the 6 poses %.4f -> %.6f m/s^2\n", rep.norm_rms_before,
              rep.norm_rms_after);
  std::printf("accel diag %.4f %.4f %.4f (sigma %.1e %.1e %.1e)\n", a.M(0, 0), a.M(1, 1), a.M(2, 2),
              a.M_sigma(0, 0), a.M_sigma(1, 1), a.M_sigma(2, 2));
  std::printf("gyro diag %.4f %.4f %.4f (sigma %.1e %.1e %.1e)\n", g.M(0, 0), g.M(1, 1), g.M(2, 2),
              g.M_sigma(0, 0), g.M_sigma(1, 1), g.M_sigma(2, 2));
}

}  // namespace
}  // namespace graftnav
