#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/multi_position.h"
#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/rotation.h"
#include "test_calib_signals.h"
#include "test_support.h"

namespace graftnav {
namespace {

// n_poses random attitudes held static_s each, joined by constant-rate rotations of move_s.
// cycle > 0: the attitudes repeat with that period (cycle distinct attitudes).
ImuSeries synthMultiPosition(test::SynthSensor& sensor, int n_poses, double static_s, double move_s,
                             double hz, unsigned seed, int cycle = 0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  std::vector<Eigen::Matrix3d> fixed;
  for (int k = 0; k < cycle; ++k)
    fixed.push_back(dcmFromEuler(Eigen::Vector3d(u(rng), 0.5 * u(rng), u(rng))));
  const Geodetic lab = test::labSite();
  const Eigen::Vector3d g_n = earth::gravity_n(lab);
  ImuSeries out;
  double t = 1000.0;
  const double dt = 1.0 / hz;
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity();
  for (int p = 0; p < n_poses; ++p) {
    const ImuSeries s = test::synthStatic(sensor, C, lab, static_s, hz, t);
    out.insert(out.end(), s.begin(), s.end());
    t = out.back().t_s;
    if (p + 1 == n_poses) break;
    const Eigen::Matrix3d Cn = cycle > 0
                                   ? fixed[(p + 1) % cycle]
                                   : dcmFromEuler(Eigen::Vector3d(u(rng), 0.5 * u(rng), u(rng)));
    const Eigen::Vector3d w =
        rotationVectorFromQuat(Eigen::Quaterniond(C.transpose() * Cn)) / move_s;
    const int n = static_cast<int>(std::lround(move_s * hz));
    for (int k = 1; k <= n; ++k) {
      const Eigen::Matrix3d Cm = C * dcmFromRotationVector(w * (k - 0.5) * dt);
      out.push_back(sensor.measure(t + k * dt, dt,
                                   w + Cm.transpose() * earth::omega_ie_n(lab.lat_rad),
                                   -Cm.transpose() * g_n));
    }
    t += n * dt;
    C = C * dcmFromRotationVector(w * n * dt);
  }
  return out;
}

TEST(CalibStaticDetector, FindsEveryPoseOfASyntheticSession) {
  test::SynthErrors e;
  e.white_g = 0.3 * kDegToRad / 60.0;
  e.white_a = 0.1 / 60.0;
  test::SynthSensor sensor(e, 4);
  const ImuSeries imu = synthMultiPosition(sensor, 12, 4.0, 2.0, 100.0, 4);
  StaticDetectorOptions o;
  o.min_duration_s = 2.0;
  const StaticDetection d = detectStaticIntervals(imu, o);
  ASSERT_EQ(d.intervals.size(), 12u);
  for (std::size_t k = 0; k < d.intervals.size(); ++k) {
    // Pose k occupies [1000 + 6k, 1004 + 6k]; the detected interval lies inside, >= 3 s long.
    EXPECT_GE(d.intervals[k].t_begin_s, 1000.0 + 6.0 * k - 1e-9);
    EXPECT_LE(d.intervals[k].t_end_s, 1004.0 + 6.0 * k + 1e-9);
    EXPECT_GT(d.intervals[k].duration(), 3.0);
  }
  // Adaptive thresholds from an initial static interval give the same count.
  o.init_static_s = 3.0;
  o.threshold_factor = 4.0;
  EXPECT_EQ(detectStaticIntervals(imu, o).intervals.size(), 12u);
}

TEST(CalibStaticDetector, BadOptions) {
  StaticDetectorOptions o;
  o.window_s = 0.0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = {};
  o.gyro_threshold_rad_s = 0.0;
  o.accel_threshold_m_s2 = 0.0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  EXPECT_THROW(detectStaticIntervals(ImuSeries(2), StaticDetectorOptions{}), std::invalid_argument);
}

TEST(CalibMultiPosition, RecoversInjectedAccelAndGyroModel) {
  for (unsigned seed : {31u, 32u}) {
    std::mt19937_64 rng(seed);
    test::SynthErrors e;
    // Lower-triangular accel M (the observable part), full gyro M in that frame.
    e.M_a = Eigen::Matrix3d::Identity() + test::randomSmall(rng, 5e-3);
    e.M_a(0, 1) = e.M_a(0, 2) = e.M_a(1, 2) = 0.0;
    e.b_a = Eigen::Vector3d(0.05, -0.08, 0.1);
    e.M_g = Eigen::Matrix3d::Identity() + test::randomSmall(rng, 5e-3);
    e.b_g = Eigen::Vector3d(2e-3, -1e-3, 1.5e-3);
    e.white_g = 0.2 * kDegToRad / 60.0;
    e.white_a = 0.05 / 60.0;
    test::SynthSensor sensor(e, seed);
    const ImuSeries imu = synthMultiPosition(sensor, 30, 4.0, 2.0, 100.0, seed);
    MultiPositionOptions o;
    o.gravity_m_s2 = earth::gravityMagnitude(test::labSite());
    o.latitude_rad = test::labSite().lat_rad;
    o.latitude_known = true;
    const MultiPositionResult r = calibrateMultiPosition(imu, o, "synthetic");
    EXPECT_EQ(r.intervals.size(), 30u);
    EXPECT_TRUE(r.accel_converged);
    EXPECT_TRUE(r.gyro_converged);
    EXPECT_LT(r.accel_norm_rms_after, 0.2 * r.accel_norm_rms_before);
    EXPECT_LT(r.gyro_angle_rms_after, 0.2 * r.gyro_angle_rms_before);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j <= i; ++j)
        EXPECT_LT(std::abs(r.accel.M(i, j) - e.M_a(i, j)), 3.0 * r.accel.M_sigma(i, j) + 1e-9)
            << "seed " << seed << " accel M(" << i << "," << j << ")";
      EXPECT_LT(std::abs(r.accel.bias[i] - e.b_a[i]), 3.0 * r.accel.bias_sigma[i]) << "accel bias";
      for (int j = 0; j < 3; ++j)
        EXPECT_LT(std::abs(r.gyro.M(i, j) - e.M_g(i, j)), 3.0 * r.gyro.M_sigma(i, j))
            << "seed " << seed << " gyro M(" << i << "," << j << ") sigma " << r.gyro.M_sigma(i, j);
      // Gyro bias: the static means also hold the horizontal Earth rate (<= 7.3e-5 rad/s).
      EXPECT_LT(std::abs(r.gyro.bias[i] - e.b_g[i]), 3.0 * r.gyro.bias_sigma[i] + 7.3e-5);
    }
    EXPECT_LT(r.gyro.M_sigma.maxCoeff(), 3e-3);
    EXPECT_LT(r.accel.M_sigma.maxCoeff(), 1e-3);
  }
}

TEST(CalibMultiPosition, TooFewIntervalsIsAnError) {
  test::SynthErrors e;
  e.white_g = 1e-4;
  test::SynthSensor sensor(e, 2);
  const ImuSeries imu = synthMultiPosition(sensor, 6, 4.0, 2.0, 100.0, 2);
  try {
    calibrateMultiPosition(imu, MultiPositionOptions{}, "six_poses.txt");
    FAIL();
  } catch (const std::runtime_error& ex) {
    EXPECT_NE(std::string(ex.what()).find("six_poses.txt"), std::string::npos);
    EXPECT_NE(std::string(ex.what()).find("only 6"), std::string::npos) << ex.what();
  }
  MultiPositionOptions bad;
  bad.min_intervals = 5;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  // Twelve intervals but only four distinct attitudes (the start pose + a cycle of three).
  test::SynthSensor s2(e, 3);
  const ImuSeries rep = synthMultiPosition(s2, 12, 4.0, 2.0, 100.0, 3, 3);
  try {
    calibrateMultiPosition(rep, MultiPositionOptions{}, "three_attitudes.txt");
    FAIL();
  } catch (const std::runtime_error& ex) {
    EXPECT_NE(std::string(ex.what()).find("only 4 distinct attitudes"), std::string::npos)
        << ex.what();
  }
}

// Real Ferraris session (imucal raw CSV) through the multi-position method: only six distinct
// attitudes, so the accelerometer M is diagonal; it must agree with the six-position result.
TEST(CalibMultiPosition, RealFerrarisSessionAgreesWithSixPosition) {
  const std::string csv =
      test::sharedDir() + "/data/real/imucal_ferraris/raw/example_ferraris_session.csv";
  const std::string case_dir = test::sharedDir() + "/data/real/imucal_ferraris";
  GRAFTNAV_REQUIRE_SHARED_PATH(csv);
  std::ifstream f(csv);
  std::string line;
  std::getline(f, line);  // header n_samples,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z (deg/s, m/s^2)
  ImuSeries imu;
  const double dt = 1.0 / 102.4;
  while (std::getline(f, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream is(line);
    double n, g[3], a[3];
    ASSERT_TRUE(is >> n >> g[0] >> g[1] >> g[2] >> a[0] >> a[1] >> a[2]) << line;
    ImuSample s;
    s.t_s = (n + 1.0) * dt;
    s.dt_s = dt;
    for (int i = 0; i < 3; ++i) {
      s.dtheta_rad[i] = g[i] * kDegToRad * dt;
      s.dvel_m_s[i] = a[i] * dt;
    }
    imu.push_back(s);
  }
  ASSERT_EQ(imu.size(), 10376u);
  const MultiPositionResult r = calibrateMultiPosition(imu, MultiPositionOptions{}, csv);
  EXPECT_EQ(r.distinct_attitudes, 6);
  EXPECT_TRUE(r.accel_diagonal_only);
  EXPECT_GE(r.intervals.size(), 9u);
  EXPECT_LT(r.accel_norm_rms_after, 0.1 * r.accel_norm_rms_before);
  EXPECT_LT(r.gyro_angle_rms_after, r.gyro_angle_rms_before);
  const LabCalibrationReport six = calibrateLab(loadLabData(case_dir));
  for (int i = 0; i < 3; ++i) {
    const double s = std::hypot(r.accel.M_sigma(i, i), six.result.accel.M_sigma(i, i));
    EXPECT_LT(std::abs(r.accel.M(i, i) - six.result.accel.M(i, i)), 3.0 * s) << "axis " << i;
  }
  std::printf(
      "Ferraris multi-position: %zu intervals, %d attitudes; |f|-g RMS %.4f -> %.4f m/s^2\n",
      r.intervals.size(), r.distinct_attitudes, r.accel_norm_rms_before, r.accel_norm_rms_after);
}

// Real recording: Xsens raw counts of imu_tk (shared/data/real/imu_tk_xsens_calib).
TEST(CalibMultiPosition, RealImuTkXsensConverges) {
  const std::string dir = test::sharedDir() + "/data/real/imu_tk_xsens_calib/raw";
  GRAFTNAV_REQUIRE_SHARED_PATH(dir + "/xsens_acc.mat");
  const ImuSeries imu = readRawCountPair(dir + "/xsens_acc.mat", dir + "/xsens_gyro.mat");
  ASSERT_EQ(imu.size(), 51175u);
  MultiPositionOptions o;
  o.gravity_m_s2 = 9.81744;  // the value imu_tk's example uses for this recording
  o.detector.init_static_s = 50.0;
  o.detector.threshold_factor = 3.0;
  o.detector.min_duration_s = 2.0;
  const MultiPositionResult r = calibrateMultiPosition(imu, o, dir);
  // The README lists 38 static segments (a simpler gyro-only detector).
  EXPECT_GE(r.intervals.size(), 30u);
  EXPECT_LE(r.intervals.size(), 45u);
  EXPECT_TRUE(r.accel_converged);
  EXPECT_TRUE(r.gyro_converged);
  EXPECT_LT(r.accel_norm_rms_after, 0.05);  // m/s^2, from ~0.5 with the nominal scale
  EXPECT_LT(r.accel_norm_rms_after, 0.2 * r.accel_norm_rms_before);
  EXPECT_LT(r.gyro_angle_rms_after, 0.5 * r.gyro_angle_rms_before);
  std::printf(
      "imu_tk: %zu static intervals; |f|-g RMS %.4f -> %.4f m/s^2; gravity-direction RMS "
      "%.3f -> %.3f deg\n",
      r.intervals.size(), r.accel_norm_rms_before, r.accel_norm_rms_after,
      r.gyro_angle_rms_before * kRadToDeg, r.gyro_angle_rms_after * kRadToDeg);
}

}  // namespace
}  // namespace graftnav
