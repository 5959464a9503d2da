// The initial alignment of core/estimation (alignment.h), on the EKF test scenarios of
// tests/support.
#include <gtest/gtest.h>

#include "ekf_scenario.h"
#include "graftnav/estimation/alignment.h"

namespace graftnav {
namespace {

ImuSeries staticImu(const Eigen::Vector3d& euler, const Geodetic& pos, double seconds,
                    const ImuProfile& p, unsigned seed) {
  const Eigen::Matrix3d C_bn = dcmFromEuler(euler).transpose();
  const Eigen::Vector3d f_b = C_bn * (-earth::gravity_n(pos));
  const Eigen::Vector3d w_b = C_bn * earth::omega_ie_n(pos.lat_rad);
  ImuSeries ideal;
  const double dt = 0.01;
  for (int k = 1; k <= static_cast<int>(seconds / dt); ++k) {
    ImuSample s;
    s.t_s = k * dt;
    s.dt_s = dt;
    s.dtheta_rad = w_b * dt;
    s.dvel_m_s = f_b * dt;
    ideal.push_back(s);
  }
  return test::corrupt(ideal, {}, p, seed);
}

TEST(Alignment, StaticNavigationGradeFindsHeadingFromEarthRate) {
  ImuProfile p;  // navigation grade (seed Table 1, POS830)
  p.arw_rad_sqrt_s = 0.0022 * kDegToRad / 60.0;
  p.vrw_m_s_sqrt_s = 0.00075 / 60.0;
  p.gyro_bias_instability_rad_s = 0.005 * kDegToRad / 3600.0;
  p.accel_bias_instability_m_s2 = 0.025e-3 * 9.80665;
  const Geodetic pos{30.5 * kDegToRad, 114.0 * kDegToRad, 20.0};
  const Eigen::Vector3d e(2.0 * kDegToRad, -3.0 * kDegToRad, 40.0 * kDegToRad);
  const StaticAlignment a = alignStatic(staticImu(e, pos, 300.0, p, 1), 0.0, 300.0, pos, p);
  ASSERT_TRUE(a.heading_valid) << a.note;
  EXPECT_NEAR(a.euler_rad.x(), e.x(), 1e-4);
  EXPECT_NEAR(a.euler_rad.y(), e.y(), 1e-4);
  EXPECT_NEAR(wrapAngle(a.euler_rad.z() - e.z()), 0.0, std::max(3.0 * a.heading_std_rad, 1e-3));
}

TEST(Alignment, StaticMemsRefusesHeadingAndSaysWhy) {
  const ImuProfile p = test::memsProfile();
  const Geodetic pos{30.5 * kDegToRad, 114.0 * kDegToRad, 20.0};
  const Eigen::Vector3d e(-1.0 * kDegToRad, 4.0 * kDegToRad, -120.0 * kDegToRad);
  const StaticAlignment a = alignStatic(staticImu(e, pos, 60.0, p, 2), 0.0, 60.0, pos, p);
  EXPECT_FALSE(a.heading_valid);
  EXPECT_NE(a.note.find("refused"), std::string::npos);
  EXPECT_NEAR(a.euler_rad.x(), e.x(), 0.05 * kDegToRad);  // levelling still works
  EXPECT_NEAR(a.euler_rad.y(), e.y(), 0.05 * kDegToRad);
}

TEST(Alignment, StaticRejectsMovingData) {
  const test::Scenario sc = test::makeDrive(60.0, 100.0);
  const Geodetic pos = sc.initial.pos;
  // Shake: add 3 m/s^2 along x so |f| is no longer g.
  ImuSeries imu = sc.ideal;
  for (auto& s : imu) s.dvel_m_s.x() += 3.0 * s.dt_s;
  EXPECT_THROW(alignStatic(imu, sc.initial.t_s, 30.0, pos, test::memsProfile()),
               std::invalid_argument);
}

TEST(Alignment, InMotionHeadingFromGnssVelocity) {
  const test::Scenario sc = test::makeDrive(120.0, 100.0);
  const Eigen::Vector3d lever(0.5, 0.0, -1.0);
  const GnssSeries g = test::makeGnss(sc.truth, lever, 100, 0.02, 4);
  const auto st = alignInMotion(sc.ideal, g, lever);
  ASSERT_TRUE(st.has_value());
  auto it = std::lower_bound(sc.truth.begin(), sc.truth.end(), st->t_s - 1e-6,
                             [](const NavState& s, double x) { return s.t_s < x; });
  const Eigen::Vector3d et = eulerFromQuat(it->q_nb), ea = eulerFromQuat(st->q_nb);
  EXPECT_GT(it->v_n.head<2>().norm(), 3.0);
  EXPECT_NEAR(wrapAngle(ea.z() - et.z()), 0.0, 2.0 * kDegToRad);
  EXPECT_NEAR(ea.x(), et.x(), 1.0 * kDegToRad);
  EXPECT_NEAR(ea.y(), et.y(), 1.0 * kDegToRad);
  EXPECT_LT((st->v_n - it->v_n).norm(), 0.2);
  EXPECT_LT(earth::nedFromGeodetic(it->pos, st->pos).norm(), 0.1);
}

}  // namespace
}  // namespace graftnav
