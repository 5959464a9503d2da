#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graftnav/nav/earth.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

// A car on a circle of radius R at speed V (NED offsets around a base point), 100 Hz.
struct CircleTrack {
  Geodetic base{0.7, 2.0, 50.0};
  double R = 150.0, V = 12.0;
  Eigen::Vector3d ned(double t) const {
    const double a = V * t / R;
    return Eigen::Vector3d(R * std::sin(a), R * (1.0 - std::cos(a)), 0.0);
  }
  Eigen::Vector3d vel(double t) const {
    const double a = V * t / R;
    return Eigen::Vector3d(V * std::cos(a), V * std::sin(a), 0.0);
  }
  Geodetic at(const Eigen::Vector3d& d) const { return earth::geodeticFromNed(base, d); }
  NavSeries series(double t0, double t1) const {
    NavSeries s;
    for (double t = t0; t <= t1 + 1e-9; t += 0.01) {
      NavState x;
      x.t_s = t;
      x.pos = at(ned(t));
      x.v_n = vel(t);
      const double yaw = std::atan2(x.v_n.y(), x.v_n.x());
      x.q_nb = quatFromEuler(Eigen::Vector3d(0, 0, yaw));
      s.push_back(x);
    }
    return s;
  }
};

GnssSeries fixesWithLatency(const CircleTrack& c, double latency, double noise_m, unsigned seed,
                            const Eigen::Vector3d& lever_b = Eigen::Vector3d::Zero()) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise_m);
  GnssSeries g;
  for (double t = 2.0; t < 58.0; t += 1.0) {
    const double tm = t - latency;  // measured earlier than stamped
    const double yaw = std::atan2(c.vel(tm).y(), c.vel(tm).x());
    const Eigen::Vector3d ant =
        c.ned(tm) + quatFromEuler(Eigen::Vector3d(0, 0, yaw)).toRotationMatrix() * lever_b;
    GnssFix f;
    f.t_s = t;
    f.pos = c.at(ant + Eigen::Vector3d(n(rng), n(rng), n(rng)));
    f.fix_type = 4;
    g.push_back(f);
  }
  return g;
}

TEST(GnssLatency, RecoversInjectedLatencyOnACircle) {
  CircleTrack c;
  const NavSeries track = c.series(0.0, 60.0);
  for (double tau : {0.4, -0.25}) {
    const GnssSeries g = fixesWithLatency(c, tau, 0.02, 7);
    const LatencyEstimate e = estimateGnssLatency(track, g, Eigen::Vector3d::Zero());
    // 2 cm noise at 12 m/s: sigma of tau ~ 0.02/12/sqrt(56) ~ 0.3 ms; the grid+parabola is
    // limited by the curvature of the circle, allow 5 ms.
    EXPECT_NEAR(e.grid_s, tau, 0.005) << tau;
    EXPECT_NEAR(e.slope_s, tau, 0.01) << tau;
    EXPECT_GT(e.rms_h_at_zero_m, 10.0 * e.grid_rms_h_m);
    EXPECT_EQ(e.fixes_used, static_cast<int>(g.size()));
  }
}

TEST(GnssLatency, LeverArmIsRemovedBeforeTheResidual) {
  CircleTrack c;
  const NavSeries track = c.series(0.0, 60.0);
  const Eigen::Vector3d lever(1.5, 0.0, -1.0);  // antenna 1.5 m forward, 1 m up
  const GnssSeries g = fixesWithLatency(c, 0.3, 0.0, 1, lever);
  const auto res = fixResiduals(track, g, 0.3, lever);
  ASSERT_FALSE(res.empty());
  for (const auto& r : res) EXPECT_LT(r.r_ned_m.norm(), 0.01);
  // Without the lever arm the forward offset would look like a latency of -1.5/12 s.
  const LatencyEstimate wrong = estimateGnssLatency(track, g, Eigen::Vector3d::Zero());
  EXPECT_NEAR(wrong.slope_s, 0.3 - 1.5 / 12.0, 0.01);
}

TEST(GnssLatency, RestFixesCarryNoInformationAndTooFewThrow) {
  CircleTrack c;
  c.V = 0.0;
  const NavSeries track = c.series(0.0, 60.0);
  const GnssSeries g = fixesWithLatency(c, 0.4, 0.01, 3);
  EXPECT_THROW(estimateGnssLatency(track, g, Eigen::Vector3d::Zero()), std::invalid_argument);
}

TEST(GnssCheckpoints, ErrorsOnlyInsideWindowsAndKnownValues) {
  CircleTrack c;
  const NavSeries track = c.series(0.0, 60.0);
  GnssSeries g = fixesWithLatency(c, 0.0, 0.0, 1);
  // Shift every check point 3 m north, 4 m east and 2 m up: horizontal error 5 m, vertical 2 m.
  for (auto& f : g) {
    const Eigen::Vector3d d = earth::nedFromGeodetic(c.base, f.pos);
    f.pos = c.at(d + Eigen::Vector3d(3.0, 4.0, -2.0));
  }
  const std::vector<TimeWindow> w = {{10.0, 20.0}, {40.0, 45.0}};
  const CheckpointEvaluation ev = evaluateAtCheckpoints(track, g, w, Eigen::Vector3d::Zero());
  ASSERT_EQ(ev.windows.size(), 2u);
  EXPECT_EQ(ev.windows[0].n, 11);
  EXPECT_EQ(ev.windows[1].n, 6);
  EXPECT_EQ(ev.n, 17);
  EXPECT_NEAR(ev.rms_h_m, 5.0, 0.01);
  EXPECT_NEAR(ev.rms_v_m, 2.0, 0.01);
  EXPECT_NEAR(ev.rms_of_max_h_m, 5.0, 0.01);
}

}  // namespace
}  // namespace graftnav
