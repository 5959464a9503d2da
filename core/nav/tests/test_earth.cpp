#include <gtest/gtest.h>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

TEST(Earth, NormalGravityAndRadii) {
  // Somigliana normal gravity of WGS-84 on the ellipsoid: 9.7803253359 at the equator,
  // 9.8321849378 at the pole (NIMA TR8350.2).
  EXPECT_NEAR(earth::gravityMagnitude({0.0, 0.0, 0.0}), 9.7803253359, 1e-8);
  EXPECT_NEAR(earth::gravityMagnitude({M_PI / 2, 0.0, 0.0}), 9.8321849378, 1e-8);
  // Free-air gradient about -3.086e-6 /s^2 per metre.
  const double g0 = earth::gravityMagnitude({0.5, 0.0, 0.0});
  const double g1 = earth::gravityMagnitude({0.5, 0.0, 1000.0});
  EXPECT_NEAR((g1 - g0) / 1000.0, -3.086e-6, 0.01e-6);
  const auto r = earth::radiiOfCurvature(0.0);
  EXPECT_NEAR(r.prime_vertical_m, 6378137.0, 1e-6);
  EXPECT_NEAR(r.meridian_m, 6335439.327, 1e-3);
}

TEST(Earth, GeodeticEcefNedRoundTrip) {
  const Geodetic o{30.5 * M_PI / 180, 114.4 * M_PI / 180, 20.0};
  const Eigen::Vector3d ned(1234.5, -987.6, 12.3);
  const Geodetic p = earth::geodeticFromNed(o, ned);
  EXPECT_LT((earth::nedFromGeodetic(o, p) - ned).norm(), 1e-6);
  const Geodetic q = earth::geodeticFromEcef(earth::ecefFromGeodetic(p));
  EXPECT_NEAR(q.lat_rad, p.lat_rad, 1e-13);
  EXPECT_NEAR(q.h_m, p.h_m, 1e-6);
  // A small offset agrees with the exact conversion to curvature order.
  const Geodetic s = earth::offsetByNed(o, {10.0, 5.0, -2.0});
  EXPECT_LT((earth::nedFromGeodetic(o, s) - Eigen::Vector3d(10, 5, -2)).norm(), 1e-4);
}

// One hour of ideal static data at 30 deg latitude, mechanized, drifts under 1 cm.
TEST(Mechanization, OneHourStaticAt30DegDriftsUnderOneCentimetre) {
  NavState s0;
  s0.pos = {30.0 * M_PI / 180.0, 114.0 * M_PI / 180.0, 50.0};
  s0.q_nb = quatFromEuler({0.02, -0.01, 1.0});
  const Eigen::Matrix3d C_bn = s0.q_nb.toRotationMatrix().transpose();
  const double dt = 0.005;
  // At rest omega_ib_b = C_bn omega_ie_n and f_b = -C_bn g_n, constant: exact increments.
  ImuSample imu;
  imu.dt_s = dt;
  imu.dtheta_rad = C_bn * earth::omega_ie_n(s0.pos.lat_rad) * dt;
  imu.dvel_m_s = -C_bn * earth::gravity_n(s0.pos) * dt;
  Strapdown sd(s0);
  const int n = static_cast<int>(3600.0 / dt);
  for (int k = 1; k <= n; ++k) {
    imu.t_s = k * dt;
    sd.step(imu);
  }
  const Eigen::Vector3d d = earth::nedFromGeodetic(s0.pos, sd.state().pos);
  EXPECT_LT(d.head<2>().norm(), 0.01) << d.transpose();
  EXPECT_LT(std::abs(d.z()), 0.01) << d.transpose();
  EXPECT_LT(sd.state().v_n.norm(), 1e-5);
  const Eigen::Vector3d dq = rotationVectorFromQuat(s0.q_nb.conjugate() * sd.state().q_nb);
  EXPECT_LT(dq.norm(), 1e-8);
}

}  // namespace
}  // namespace graftnav
