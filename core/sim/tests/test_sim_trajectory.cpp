// Simulator trajectories and the ideal IMU: exactness checks and the strapdown round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sim/track_trajectory.h"
#include "test_support.h"

namespace graftnav {
namespace {

std::string fmtNum(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.3e", v);
  return b;
}

GnssSeries trackPiece(double from_s, double to_s) {
  const GnssSeries all =
      readGnssPos(test::sharedDir() + "/data/tracks/wuhan_57min_rtk.pos", GnssReadPolicy::real());
  GnssSeries out;
  for (const auto& f : all)
    if (f.t_s >= all.front().t_s + from_s && f.t_s <= all.front().t_s + to_s) out.push_back(f);
  return out;
}

// The 5-minute round trip: ideal increments of a piece of the real track, mechanized
// from the true initial state, reproduce the truth (horizontal < 5 cm, attitude < 0.001 deg).
TEST(SimTrajectory, FiveMinuteTrackRoundTrip) {
  const TrackTrajectory trj(trackPiece(900.0, 1210.0));
  const double t0 = trj.startTime_s() + 5.0, t1 = t0 + 300.0;
  const ImuSeries imu = simulateIdealImu(trj, t0, t1);
  ASSERT_EQ(imu.size(), 60000u);
  Strapdown sd(trj.navState(t0));
  double max_h = 0.0, max_att = 0.0, path = 0.0;
  Eigen::Vector3d prev = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < imu.size(); ++k) {
    sd.step(imu[k]);
    if ((k + 1) % 200 == 0) {
      const NavState truth = trj.navState(imu[k].t_s);
      const Eigen::Vector3d d = earth::nedFromGeodetic(truth.pos, sd.state().pos);
      max_h = std::max(max_h, d.head<2>().norm());
      max_att = std::max(max_att,
                         rotationVectorFromQuat(truth.q_nb.conjugate() * sd.state().q_nb).norm());
      const Eigen::Vector3d p = earth::nedFromGeodetic(trj.navState(t0).pos, truth.pos);
      path += (p - prev).norm();
      prev = p;
    }
  }
  EXPECT_GT(path, 500.0) << "the piece should contain real motion";
  EXPECT_LT(max_h, 0.05);
  EXPECT_LT(max_att * kRadToDeg, 0.001);
  RecordProperty("max_horizontal_error_m", fmtNum(max_h));
  RecordProperty("max_attitude_error_deg", fmtNum(max_att * kRadToDeg));
}

// The analytic derivatives agree with central differences of the trajectory itself: v_n with the
// motion of the position, a_n with dv_n/dt (NED components, including the transport-rate term of
// the tangent-plane conversion, ~3e-5 m/s^2 at 15 m/s), omega_nb_b with dC_nb/dt.
TEST(SimTrajectory, AnalyticDerivativesMatchCentralDifferences) {
  const TrackTrajectory trj(trackPiece(900.0, 1210.0));
  EXPECT_GT(test::expectDerivativesMatchCentralDifferences(trj, 1e-3, 1e-5, 1e-5, 1e-5), 30);
}

// The whole 57-minute track at 200 Hz (target: drift < 1 m, attitude < 0.001 deg at
// the end). About 10 s in Release.
TEST(SimTrajectory, FullTrack57MinRoundTrip) {
  const TrackTrajectory trj(trackPiece(0.0, 1e9));
  const TrackFitReport& rep = trj.report();
  EXPECT_GT(rep.fixes_used, 3300);
  EXPECT_LT(rep.rms_residual_m[0], 0.06);
  EXPECT_LT(rep.rms_residual_m[1], 0.06);
  const double t0 = trj.startTime_s(), t1 = trj.endTime_s();
  const ImuSeries imu = simulateIdealImu(trj, t0, t1);
  Strapdown sd(trj.navState(t0));
  for (const auto& s : imu) sd.step(s);
  const NavState truth = trj.navState(imu.back().t_s);
  const Eigen::Vector3d d = earth::nedFromGeodetic(truth.pos, sd.state().pos);
  const double att = rotationVectorFromQuat(truth.q_nb.conjugate() * sd.state().q_nb).norm();
  EXPECT_LT(d.head<2>().norm(), 0.01);  // target 1 m; measured 0.17 mm
  EXPECT_LT(att * kRadToDeg, 1e-6);     // target 1e-3 deg; measured 3e-9 deg
  RecordProperty("end_horizontal_error_m", fmtNum(d.head<2>().norm()));
  RecordProperty("end_vertical_error_m", fmtNum(d.z()));
  RecordProperty("end_attitude_error_deg", fmtNum(att * kRadToDeg));
  RecordProperty("end_velocity_error_m_s", fmtNum((truth.v_n - sd.state().v_n).norm()));
  RecordProperty("fit_rms_residual_ned_m", fmtNum(rep.rms_residual_m[0]) + " " +
                                               fmtNum(rep.rms_residual_m[1]) + " " +
                                               fmtNum(rep.rms_residual_m[2]));
  RecordProperty("fit_rejected_stops",
                 std::to_string(rep.fixes_rejected) + " " + std::to_string(rep.stops));
}

}  // namespace
}  // namespace graftnav
