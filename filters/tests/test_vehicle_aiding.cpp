// Odometer and NHC in the EKF and the RTS smoother: the measurement model against the
// simulator's, its Jacobian against a numeric one, and a car drive (the simulator's motion
// script, a MEMS IMU, 1 Hz GNSS with a 60 s outage, an odometer 3000 ppm fast with 0.05 m/s
// noise) on which aiding must shrink the outage error and recover the scale within 3 sigma.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ekf_scenario.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/filters/rts_smoother.h"
#include "graftnav/filters/vehicle_velocity.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sim/motion_script.h"
#include "graftnav/sim/odometer_simulator.h"
#include "test_support.h"
#include "vehicle_scenario.h"

namespace graftnav {
namespace {

using namespace ekf;

VehicleGeometry geometry() {
  VehicleAidingOptions a;
  a.odometer.mounting_rad << 0.4 * kDegToRad, -1.2 * kDegToRad, 2.5 * kDegToRad;
  VehicleGeometry g;
  g.C_vb = a.C_vb();
  g.lever_arm_b_m << -0.8, 0.6, 0.9;
  return g;
}

using test::movingState;

TEST(VehicleVelocity, JacobianMatchesNumeric) {
  const NavState t = movingState();
  const VehicleGeometry g = geometry();
  const Eigen::Vector3d omega(0.05, -0.08, 0.3);
  const Eigen::Vector3d v_true = vehicleVelocity(t, omega, g);
  auto f = [&](const Eigen::VectorXd& xv) -> Eigen::VectorXd {
    const ErrorState x = xv;
    const Eigen::Vector3d w = test::perturbedBodyRate(omega, x);
    return vehicleVelocity(perturbNavState(t, x), w, g) - v_true;
  };
  const Eigen::MatrixXd Hn = test::numericJacobian(f, Eigen::VectorXd::Zero(kStateDim), 1e-4);
  const auto H = vehicleVelocityJacobian(t, omega, g);
  EXPECT_LT((Hn - H).cwiseAbs().maxCoeff(), 1e-6) << Hn << "\n\n" << H;
  const double lever_term = H.block<3, 3>(0, kGyroBias).cwiseAbs().maxCoeff();
  EXPECT_GT(lever_term, 0.1);  // the lever arm is seen
}

// The EKF's model and the simulator's truth readings agree at every point of a drive.
TEST(VehicleVelocity, EqualsTheSimulatorsOdometerPointVelocity) {
  MotionScript m;
  m.start_time_s = 1000.0;
  m.start = {30.5 * kDegToRad, 114.3 * kDegToRad, 20.0};
  m.segments = {{MotionSegment::Type::kAccelerate, 10.0, 12.0},
                {MotionSegment::Type::kTurn, 9.0, 0.0, 12.0 * kDegToRad}};
  const ScriptTrajectory trj(m);
  const VehicleGeometry g = geometry();
  for (double t = 1000.5; t < 1018.0; t += 1.3) {
    const TrajectoryPoint p = trj.at(t);
    NavState s = trj.navState(t);
    const Eigen::Vector3d want = odometerPointVelocity_v(p, g.C_vb, g.lever_arm_b_m);
    const Eigen::Vector3d got = vehicleVelocity(s, bodyRates(p).omega_ib_b, g);
    EXPECT_LT((got - want).norm(), 1e-9) << t;
  }
}

TEST(VehicleAiding, OdometerAndNhcShrinkTheEkfAndRtsOutageErrorAndRecoverTheScale) {
  test::VehicleDrive d = test::makeVehicleDrive();
  const NavSolution ekf_free = runEkf(d.problem, EkfOptions{});
  const NavSolution rts_free = runRts(d.problem, EkfOptions{});
  EXPECT_TRUE(ekf_free.odometer_scale.empty());
  test::enableVehicleAiding(&d.problem, true, true);
  const NavSolution ekf = runEkf(d.problem, EkfOptions{});
  const NavSolution rts = runRts(d.problem, EkfOptions{});
  const double e_free = test::outageHorizontalRms(ekf_free, d),
               e_aid = test::outageHorizontalRms(ekf, d);
  const double r_free = test::outageHorizontalRms(rts_free, d),
               r_aid = test::outageHorizontalRms(rts, d);
  std::printf("outage horizontal RMS: ekf %.3f -> %.3f m, rts %.3f -> %.3f m\n", e_free, e_aid,
              r_free, r_aid);
  EXPECT_LT(e_aid, 0.25 * e_free);
  EXPECT_LT(r_aid, 0.5 * r_free);
  EXPECT_GT(ekf.vehicle_used, 3000);
  EXPECT_LT(ekf.vehicle_rejected, ekf.vehicle_used / 50);
  // The scale: estimated within 3 sigma, and the sigma far below its initial 1 %.
  for (const NavSolution* s : {&ekf, &rts}) {
    ASSERT_EQ(s->odometer_scale.size(), s->states.size()) << s->estimator;
    const double k = s->odometer_scale.back(), sd = s->odometer_scale_std.back();
    std::printf("%s odometer scale %.0f +- %.0f ppm (true %.0f)\n", s->estimator.c_str(), k * 1e6,
                sd * 1e6, test::kVehicleDriveScaleError * 1e6);
    EXPECT_LT(std::abs(k - test::kVehicleDriveScaleError), 3.0 * sd) << s->estimator;
    EXPECT_LT(sd, 300e-6) << s->estimator;
  }
}

TEST(VehicleAiding, NhcAloneHelpsAndEstimatesNoScale) {
  test::VehicleDrive d = test::makeVehicleDrive();
  const double e_free = test::outageHorizontalRms(runEkf(d.problem, EkfOptions{}), d);
  test::enableVehicleAiding(&d.problem, false, true);
  const NavSolution ekf = runEkf(d.problem, EkfOptions{});
  EXPECT_TRUE(ekf.odometer_scale.empty());
  EXPECT_LT(test::outageHorizontalRms(ekf, d), 0.8 * e_free);
}

TEST(VehicleAiding, BadOptionsNameTheField) {
  EstimationProblem p = test::makeVehicleDrive().problem;
  test::enableVehicleAiding(&p, true, false);
  p.aiding.odometer.scale_std = 3000.0;  // ppm given as a fraction
  try {
    runEkf(p, EkfOptions{});
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("odometer.scale_std"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace graftnav
