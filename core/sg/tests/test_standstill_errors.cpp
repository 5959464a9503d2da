// Standstill spans of a field recording as a basic error signal: the GNSS speed filter, and the
// error increments (measured minus gravity and Earth rate at rest) that keep the gyro bias and
// the vertical accelerometer bias.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sg/standstill_errors.h"

namespace graftnav {
namespace {

constexpr double kDt = 0.01;

Geodetic wuhan() {
  Geodetic p;
  p.lat_rad = 30.5 * kDegToRad;
  p.lon_rad = 114.3 * kDegToRad;
  p.h_m = 20.0;
  return p;
}

// The output at rest of a level-ish IMU at heading yaw, plus constant biases.
ImuSample atRest(double t, const Geodetic& pos, const Eigen::Vector3d& rpy,
                 const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& accel_bias) {
  const Eigen::Matrix3d C_nb = quatFromEuler(rpy).toRotationMatrix();
  const Eigen::Vector3d f_b =
      C_nb.transpose() * Eigen::Vector3d(0.0, 0.0, -earth::gravityMagnitude(pos));
  const Eigen::Vector3d w_b = C_nb.transpose() * earth::omega_ie_n(pos.lat_rad);
  ImuSample s;
  s.t_s = t;
  s.dt_s = kDt;
  s.dtheta_rad = (w_b + gyro_bias) * kDt;
  s.dvel_m_s = (f_b + accel_bias) * kDt;
  return s;
}

TEST(StandstillErrors, IncrementsKeepTheGyroBiasAndTheVerticalAccelBias) {
  const Geodetic pos = wuhan();
  const Eigen::Vector3d rpy(0.02, -0.01, 1.2);
  const Eigen::Vector3d bg(1e-4, -2e-4, 3e-4), ba(0.0, 0.0, 0.02);
  ImuSeries imu;
  for (int k = 1; k <= 2000; ++k) imu.push_back(atRest(k * kDt, pos, rpy, bg, ba));
  StaticInterval a, b;
  a.begin = 100, a.end = 600;
  b.begin = 1200, b.end = 1900;
  const ImuSeries err = staticErrorIncrements(imu, {a, b}, pos, rpy.z());
  ASSERT_EQ(err.size(), 1200u);
  EXPECT_NEAR(err.front().t_s, kDt, 1e-12);  // its own time axis from 0
  EXPECT_NEAR(err.back().t_s, 1200 * kDt, 1e-9);
  for (const auto& s : {err.front(), err[700], err.back()}) {
    // The gyro bias stays (to the Earth rate's small tilt effect); the accel bias along the
    // specific force stays, its horizontal part would be absorbed by the levelling.
    EXPECT_NEAR((s.dtheta_rad / kDt - bg).norm(), 0.0, 1e-8);
    EXPECT_NEAR((s.dvel_m_s / kDt).norm(), ba.norm(), 1e-4);
  }
}

TEST(StandstillErrors, SpansWhereGnssMovesAreDropped) {
  const Geodetic pos = wuhan();
  ImuSeries imu;
  for (int k = 1; k <= 3000; ++k) {
    ImuSample s = atRest(k * kDt, pos, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                         Eigen::Vector3d::Zero());
    if (k > 1000 && k <= 1200)
      s.dtheta_rad.z() += 0.5 * kDt * std::sin(k * 0.3);  // a turn splits the record
    imu.push_back(s);
  }
  GnssSeries gnss;
  for (int t = 0; t <= 30; ++t) {
    GnssFix f;
    f.t_s = t;
    f.pos = pos;
    if (t > 12)
      f.pos.lat_rad +=
          (t - 12) * 2.0 / earth::semiMajorAxis_m();  // drives north at ~2 m/s after 12 s
    gnss.push_back(f);
  }
  StandstillOptions o;
  const StandstillSpans sp = findStandstills(imu, gnss, o);
  ASSERT_EQ(sp.detection.intervals.size(), 2u);
  ASSERT_EQ(sp.kept.size(), 1u);
  EXPECT_EQ(sp.dropped_moving, 1);
  EXPECT_LT(sp.kept.front().t_end_s, 10.5);
  EXPECT_NEAR(medianGnssChordSpeed(gnss, 13.0, 30.0, 1.0), 2.0, 0.05);
  EXPECT_EQ(medianGnssChordSpeed(gnss, 0.0, 10.0, 1.0), 0.0);

  o.max_gnss_speed_m_s = 5.0;  // a slow drive now counts as a standstill
  EXPECT_EQ(findStandstills(imu, gnss, o).kept.size(), 2u);
  o.max_gnss_speed_m_s = 0.0;
  EXPECT_THROW(findStandstills(imu, gnss, o), std::invalid_argument);
  GnssSeries all_moving = gnss;
  for (auto& f : all_moving) f.pos.lat_rad += f.t_s * 2.0 / earth::semiMajorAxis_m();
  o.max_gnss_speed_m_s = 0.3;
  EXPECT_THROW(findStandstills(imu, all_moving, o), std::runtime_error);
}

}  // namespace
}  // namespace graftnav
