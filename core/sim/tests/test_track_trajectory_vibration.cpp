// Road/engine vibration of the TrackTrajectory (RoadVibrationOptions, track_trajectory.h): its
// specific-force and angular-rate rms match the request, it fades out when the car stops, its
// analytic derivatives are exact, mechanizing the ideal increments of a vibrating track still
// reproduces the truth, and the sim config parses and validates the trajectory.vibration keys.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sim/sim_config.h"
#include "graftnav/sim/track_trajectory.h"
#include "graftnav/nav/units.h"
#include "test_support.h"

namespace graftnav {
namespace {

RoadVibrationOptions carVibration() {
  RoadVibrationOptions v;
  v.accel_rms_m_s2 = 0.8;
  v.gyro_rms_rad_s = 0.3 * units::kDegToRad;
  v.band_low_hz = 8.0;
  v.band_high_hz = 35.0;
  v.components = 12;
  v.seed = 3;
  v.half_amplitude_speed_m_s = 5.0;
  return v;
}

// 1 Hz fixes of a car driving east with speed profile speed_m_s(t) (integrated at 1 ms).
template <class Speed>
GnssSeries syntheticTrack(double duration_s, Speed speed_m_s) {
  const Geodetic origin{30.5 * units::kDegToRad, 114.3 * units::kDegToRad, 20.0};
  GnssSeries out;
  double east_m = 0.0;
  const double h = 1e-3;
  for (int k = 0; k <= static_cast<int>(duration_s); ++k) {
    GnssFix f;
    f.t_s = 1000.0 + k;
    f.pos = earth::geodeticFromNed(origin, Eigen::Vector3d(0.0, east_m, 0.0));
    f.std_ned_m = Eigen::Vector3d(0.01, 0.01, 0.02);
    f.fix_type = 4;
    out.push_back(f);
    for (int i = 0; i < 1000; ++i) east_m += h * speed_m_s(k + (i + 0.5) * h);
  }
  return out;
}

TrackSmoothingOptions withVibration(const RoadVibrationOptions& v) {
  TrackSmoothingOptions o;
  o.vibration = v;
  return o;
}

GnssSeries realTrackPiece(double from_s, double to_s) {
  GnssSeries out;
  for (const auto& f : readGnssPos(test::sharedDir() + "/data/tracks/wuhan_57min_rtk.pos",
                                   GnssReadPolicy::real())) {
    if (out.empty() && f.t_s < 0.0) continue;
    out.push_back(f);
  }
  const double t0 = out.front().t_s;
  GnssSeries piece;
  for (const auto& f : out)
    if (f.t_s >= t0 + from_s && f.t_s <= t0 + to_s) piece.push_back(f);
  return piece;
}

// Mean squares per body axis of the vibration (vibrating minus still trajectory) at 1 kHz.
struct VibrationPower {
  Eigen::Vector3d f_ms = Eigen::Vector3d::Zero();  // (m/s^2)^2
  Eigen::Vector3d w_ms = Eigen::Vector3d::Zero();  // (rad/s)^2
  double f_max = 0.0;
};
VibrationPower vibrationPower(const Trajectory& vib, const Trajectory& still, double t0,
                              double t1) {
  VibrationPower p;
  int n = 0;
  for (double t = t0; t < t1; t += 1e-3, ++n) {
    const BodyRates a = bodyRates(vib.at(t)), b = bodyRates(still.at(t));
    const Eigen::Vector3d df = a.f_b - b.f_b, dw = a.omega_ib_b - b.omega_ib_b;
    p.f_ms += df.cwiseProduct(df);
    p.w_ms += dw.cwiseProduct(dw);
    p.f_max = std::max(p.f_max, df.norm());
  }
  p.f_ms /= n;
  p.w_ms /= n;
  return p;
}

// At a steady 20 m/s the amplitude factor is m = 20^2 / (20^2 + 5^2); the vector rms of the
// vibration must be m times the request (3 %: cross terms of sinusoids a few tenths of a Hz
// apart do not average out completely over 200 s), with most of it on the down axis.
TEST(TrackTrajectoryVibration, RmsMatchesTheConfigAtSteadySpeed) {
  const GnssSeries track = syntheticTrack(300.0, [](double) { return 20.0; });
  const RoadVibrationOptions v = carVibration();
  const TrackTrajectory vib(track, withVibration(v)), still(track);
  const double m = 400.0 / 425.0;
  const VibrationPower p =
      vibrationPower(vib, still, vib.startTime_s() + 50.0, vib.startTime_s() + 250.0);
  const double f_rms = std::sqrt(p.f_ms.sum()), w_rms = std::sqrt(p.w_ms.sum());
  EXPECT_NEAR(f_rms / (m * v.accel_rms_m_s2), 1.0, 0.03) << f_rms;
  EXPECT_NEAR(w_rms / (m * v.gyro_rms_rad_s), 1.0, 0.03) << w_rms;
  // Body down carries 60 % of the specific-force power, forward 15 % (heading east: the heading
  // frame is rotated by 90 deg, so this also checks the rotation).
  EXPECT_NEAR(p.f_ms.z() / p.f_ms.sum(), 0.60, 0.04);
  EXPECT_NEAR(p.f_ms.x() / p.f_ms.sum(), 0.15, 0.04);
  EXPECT_NEAR(p.w_ms.z() / p.w_ms.sum(), 0.15, 0.04);
  RecordProperty("f_rms_m_s2", std::to_string(f_rms));
  RecordProperty("w_rms_deg_s", std::to_string(w_rms * units::kRadToDeg));
}

// Speed fade: the vibration vanishes while the car stands (10 m/s, stop of 100 s, 10 m/s) and is
// m = 10^2 / (10^2 + 5^2) = 0.8 of the request while it cruises.
TEST(TrackTrajectoryVibration, FadesOutWhenStopped) {
  auto speed = [](double t) {
    auto ramp = [](double x) {
      return x <= 0 ? 0.0 : x >= 1 ? 1.0 : 0.5 - 0.5 * std::cos(M_PI * x);
    };
    return 10.0 * (1.0 - ramp((t - 100.0) / 10.0) + ramp((t - 210.0) / 10.0));
  };
  const GnssSeries track = syntheticTrack(330.0, speed);
  const RoadVibrationOptions v = carVibration();
  const TrackTrajectory vib(track, withVibration(v)), still(track);
  ASSERT_GE(still.report().stops, 1);
  const double t0 = vib.startTime_s();
  const VibrationPower stopped = vibrationPower(vib, still, t0 + 130.0, t0 + 190.0);
  const VibrationPower cruise = vibrationPower(vib, still, t0 + 20.0, t0 + 90.0);
  EXPECT_LT(stopped.f_max, 1e-3 * v.accel_rms_m_s2);
  EXPECT_LT(std::sqrt(stopped.w_ms.sum()), 1e-3 * v.gyro_rms_rad_s);
  EXPECT_NEAR(std::sqrt(cruise.f_ms.sum()) / (0.8 * v.accel_rms_m_s2), 1.0, 0.04);
  RecordProperty("stopped_max_f_m_s2", std::to_string(stopped.f_max));
}

// The analytic v_n, a_n and omega_nb_b of a vibrating real-track piece (speed and heading change,
// so the fade and heading-rotation terms are exercised: each is ~1e-3 m/s^2) agree with central
// differences (h = 30 us: truncation ~1e-5 m/s^2 at 35 Hz).
TEST(TrackTrajectoryVibration, AnalyticDerivativesMatchCentralDifferences) {
  const TrackTrajectory trj(realTrackPiece(900.0, 1210.0), withVibration(carVibration()));
  EXPECT_GT(test::expectDerivativesMatchCentralDifferences(trj, 3e-5, 1e-4, 1e-4, 1e-6), 30);
}

// Strapdown round trip on a vibrating 5-minute piece of the real track with the suite's IMU
// settings (100 Hz, 4 Gauss-Legendre nodes): the ideal increments, mechanized from the true
// initial state, reproduce the truth. Measured: horizontal 0.48 mm (0.12 mm without vibration),
// attitude 1e-6 deg; tolerances 5 mm and 1e-4 deg (the still round trip in
// test_sim_trajectory.cpp allows 5 cm and 1e-3 deg at 200 Hz).
TEST(TrackTrajectoryVibration, VibratingTrackRoundTrip) {
  const TrackTrajectory trj(realTrackPiece(900.0, 1210.0), withVibration(carVibration()));
  const double t0 = trj.startTime_s() + 5.0, t1 = t0 + 300.0;
  IdealImuOptions io;
  io.rate_hz = 100.0;
  io.quadrature_nodes = 4;
  const ImuSeries imu = simulateIdealImu(trj, t0, t1, io);
  ASSERT_EQ(imu.size(), 30000u);
  Strapdown sd(trj.navState(t0));
  double max_h = 0.0, max_att = 0.0;
  for (std::size_t k = 0; k < imu.size(); ++k) {
    sd.step(imu[k]);
    if ((k + 1) % 100 == 0) {
      const NavState truth = trj.navState(imu[k].t_s);
      max_h = std::max(max_h, earth::nedFromGeodetic(truth.pos, sd.state().pos).head<2>().norm());
      max_att = std::max(max_att,
                         rotationVectorFromQuat(truth.q_nb.conjugate() * sd.state().q_nb).norm());
    }
  }
  EXPECT_LT(max_h, 0.005);
  EXPECT_LT(max_att * units::kRadToDeg, 1e-4);
  RecordProperty("max_horizontal_error_m", std::to_string(max_h));
  RecordProperty("max_attitude_error_deg", std::to_string(max_att * units::kRadToDeg));
}

// A copy of the concealed vibration case with `vibration` replacing trajectory.vibration and the
// paths made absolute, in a temporary directory; returns the file path.
std::string configWithVibration(const std::string& tag, const YAML::Node& vibration,
                                int imu_rate_hz = 100, int nodes = 4) {
  const std::string dir = test::sourceDir() + "/configs/sim/concealed/";
  YAML::Node c = YAML::LoadFile(dir + "vibration_rectification.yaml");
  c["trajectory"]["track"] = test::sharedDir() + "/data/tracks/wuhan_57min_rtk.pos";
  c["reference_imu"]["profile"] = test::sourceDir() + "/configs/imu/pos830_navigation.yaml";
  c["tested_imu"]["profile"] = test::sourceDir() + "/configs/imu/pos1100_mems.yaml";
  c["imu_rate_hz"] = imu_rate_hz;
  c["quadrature_nodes"] = nodes;
  c["truth_rate_hz"] = 10;
  c["trajectory"].remove("vibration");
  if (vibration.IsMap()) c["trajectory"]["vibration"] = vibration;
  const std::string path = test::makeTempDir(tag) + "/case.yaml";
  std::ofstream(path) << c;
  return path;
}

TEST(TrackTrajectoryVibration, ConfigParsedInSi) {
  std::vector<std::string> warnings;
  const SimConfig c = loadSimConfig(
      configWithVibration("vib_cfg", YAML::Load("{accel_rms_m_s2: 0.8, gyro_rms_deg_s: 0.3, "
                                                "band_hz: [8, 35], components: 12, seed: 4, "
                                                "half_amplitude_speed_m_s: 6}")),
      &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const RoadVibrationOptions& v = c.track->smoothing.vibration;
  EXPECT_DOUBLE_EQ(v.accel_rms_m_s2, 0.8);
  EXPECT_DOUBLE_EQ(v.gyro_rms_rad_s, 0.3 * units::kDegToRad);
  EXPECT_DOUBLE_EQ(v.band_low_hz, 8.0);
  EXPECT_DOUBLE_EQ(v.band_high_hz, 35.0);
  EXPECT_EQ(v.components, 12);
  EXPECT_EQ(v.seed, 4u);
  EXPECT_DOUBLE_EQ(v.half_amplitude_speed_m_s, 6.0);
  const auto lin = v.linearComponents();
  ASSERT_EQ(lin.size(), 12u);
  for (const auto& o : lin) {
    EXPECT_GE(o.frequency_hz, 8.0);
    EXPECT_LE(o.frequency_hz, 35.0);
    EXPECT_LT(o.amplitude, 1e-3);  // micrometre-scale displacements
  }
  // Without the key there is no vibration.
  EXPECT_FALSE(loadSimConfig(configWithVibration("vib_none", YAML::Node()))
                   .track->smoothing.vibration.enabled());
}

void expectRejected(const std::string& tag, const std::string& vib, const std::string& key,
                    int imu_rate_hz = 100, int nodes = 4) {
  try {
    loadSimConfig(configWithVibration(tag, YAML::Load(vib), imu_rate_hz, nodes));
    ADD_FAILURE() << vib << " accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(TrackTrajectoryVibration, ConfigErrorsNameTheKey) {
  expectRejected("vib_neg", "{accel_rms_m_s2: -0.1}", "trajectory.vibration.accel_rms_m_s2");
  expectRejected("vib_band", "{accel_rms_m_s2: 0.8, band_hz: [30, 8]}",
                 "trajectory.vibration.band_hz");
  expectRejected("vib_comp", "{accel_rms_m_s2: 0.8, components: 2}",
                 "trajectory.vibration.components");
  expectRejected("vib_nyq", "{accel_rms_m_s2: 0.8, band_hz: [8, 50]}",
                 "trajectory.vibration.band_hz");
  // 2 Gauss-Legendre nodes at 100 Hz integrate 35 Hz to 6e-3 only.
  expectRejected("vib_quad", "{accel_rms_m_s2: 0.8, band_hz: [8, 35]}", "quadrature_nodes", 100, 2);
  EXPECT_NO_THROW(loadSimConfig(configWithVibration(
      "vib_ok3", YAML::Load("{accel_rms_m_s2: 0.8, band_hz: [8, 35]}"), 100, 3)));
}

}  // namespace
}  // namespace graftnav
