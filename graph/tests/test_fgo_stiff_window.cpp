// Regression for the divergence on the yandld MEMS recording: 10 Hz GNSS nodes make the
// preintegration factors ~1e8 stiffer than the GNSS-observed modes of a window; with Ceres'
// default initial trust-region radius (1e4) the Levenberg-Marquardt damping diag(J^T J)/radius
// swamps those modes, a 4-iteration window solve barely moves, and the window pass dead-reckons
// a 0.5 m/s^2 accelerometer error (km within a minute, then non-finite states in the batch).
// Also: non-finite node values are reported with the node, not written out.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "graftnav/nav/rotation.h"
#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/fgo_solver.h"
#include "graph_scenario.h"

namespace graftnav {
namespace {

// MEMS like the yandld unit: 100 Hz, z accelerometer 0.5 m/s^2 off, gyro biases ~0.08 deg/s,
// 10 Hz GNSS with 2 m noise, a profile with large initial bias sigmas.
EstimationProblem makeMemsProblem(const test::Scenario& sc) {
  test::ImuErrors err;
  err.bg_rad_s << 1.4e-3, -2e-4, 1.4e-3;  // ~0.08 deg/s
  err.ba_m_s2 << 0.02, -0.03, -0.5;       // z: 5 % of gravity
  err.arw_rad_sqrt_s = 1.75e-4;           // 0.6 deg/sqrt(h)
  err.vrw_m_s_sqrt_s = 5e-3;              // 0.3 m/s/sqrt(h)
  EstimationProblem p;
  p.imu = test::addImuErrors(sc.ideal, err, 7);
  p.lever_arm_b_m.setZero();
  p.gnss = test::makeGnss(sc, p.lever_arm_b_m, 0.1, 2.0, 8);
  p.initial = sc.truth.front();
  p.imu_profile.arw_rad_sqrt_s = err.arw_rad_sqrt_s;
  p.imu_profile.vrw_m_s_sqrt_s = err.vrw_m_s_sqrt_s;
  p.imu_profile.gyro_bias_instability_rad_s = 1.5e-4;   // 30 deg/h
  p.imu_profile.accel_bias_instability_m_s2 = 0.03;     // 3 mg
  p.imu_profile.gyro_bias_initial_std_rad_s = 1.94e-3;  // 400 deg/h
  p.imu_profile.accel_bias_initial_std_m_s2 = 0.59;     // 60 mg
  p.initial_sigma << 0.5, 0.5, 0.5, 0.3, 0.3, 0.3, 1.0 * kDegToRad, 1.0 * kDegToRad,
      3.0 * kDegToRad;
  return p;
}

// RMS 3-D position error over the last `last_s` seconds.
double finalPositionRms(const NavSolution& sol, const test::Scenario& sc, double last_s) {
  const double t_end = sc.truth.back().t_s;
  double s = 0.0;
  int n = 0;
  for (size_t k = 0; k < sol.states.size(); ++k) {
    if (sol.states[k].t_s < t_end - last_s) continue;
    EXPECT_NEAR(sol.states[k].t_s, sc.truth[k].t_s, 1e-9);
    const double e = earth::nedFromGeodetic(sc.truth[k].pos, sol.states[k].pos).norm();
    s += e * e;
    ++n;
  }
  EXPECT_GT(n, 0);
  return n > 0 ? std::sqrt(s / n) : std::numeric_limits<double>::infinity();
}

TEST(FgoStiffWindow, WindowFollows10HzGnssWithLargeAccelError) {
  const test::Scenario sc = test::makeScenario(30.0, 100.0, 10.0);
  const EstimationProblem p = makeMemsProblem(sc);
  FgoOptions opt;  // window_iterations 4 as in the batch initialization
  const NavSolution good = solveWindowFgo(p, opt);
  const double e_good = finalPositionRms(good, sc, 5.0);
  // 2 m GNSS at 10 Hz: a converging window stays within a few metres.
  EXPECT_LT(e_good, 3.0);

  // The mechanism: the same window with Ceres' default radius dead-reckons the z error
  // (0.5 m/s^2 over 30 s is ~200 m).
  opt.initial_trust_region_radius = 1e4;
  const NavSolution bad = solveWindowFgo(p, opt);
  const double e_bad = finalPositionRms(bad, sc, 5.0);
  EXPECT_GT(e_bad, 10.0 * e_good) << "good " << e_good << " m, bad " << e_bad << " m";
}

TEST(FgoStiffWindow, BatchRecoversAccelErrorWith10HzGnss) {
  const test::Scenario sc = test::makeScenario(30.0, 100.0, 10.0);
  const EstimationProblem p = makeMemsProblem(sc);
  FgoReport rep;
  const NavSolution sol = solveBatchFgo(p, FgoOptions{}, &rep);
  EXPECT_LT(finalPositionRms(sol, sc, 5.0), 2.0) << rep.summary;
  // The z accelerometer error is observable (10 Hz position, 30 s).
  EXPECT_NEAR(sol.accel_bias_m_s2.back().z(), -0.5, 0.1) << rep.summary;
}

TEST(FgoStiffWindow, NonFiniteNodeIsReportedWithItsIndex) {
  const test::Scenario sc = test::makeScenario(3.0, 100.0, 10.0);
  const EstimationProblem p = makeMemsProblem(sc);
  FgoGraph graph(p, FgoOptions{});
  ASSERT_GT(graph.nodeCount(), 5u);
  EXPECT_NO_THROW(graph.requireFinite(0, 1, "test"));
  graph.blocks(3).v[1] = std::nan("");
  try {
    graph.requireFinite(0, graph.nodeCount(), "stage-x");
    FAIL() << "no exception for a NaN velocity";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("stage-x"), std::string::npos) << msg;
    EXPECT_NE(msg.find("node 3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("velocity"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace graftnav
