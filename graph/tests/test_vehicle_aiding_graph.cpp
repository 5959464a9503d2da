// Odometer and NHC factors in the batch smoother and the sliding window, on the car drive of
// the filters' aiding test (tests/support/vehicle_scenario.h): the outage error shrinks and the
// odometer scale is recovered, through the window's marginalization prior too.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "graftnav/graph/fgo_solver.h"
#include "vehicle_scenario.h"

namespace graftnav {
namespace {

TEST(VehicleAidingGraph, OdometerAndNhcShrinkTheOutageErrorAndRecoverTheScale) {
  test::VehicleDrive d = test::makeVehicleDrive();
  FgoOptions o;
  const NavSolution fgo_free = solveBatchFgo(d.problem, o);
  const NavSolution win_free = solveWindowFgo(d.problem, o);
  test::enableVehicleAiding(&d.problem, true, true);
  FgoReport rep;
  const NavSolution fgo = solveBatchFgo(d.problem, o, &rep);
  const NavSolution win = solveWindowFgo(d.problem, o);
  const double b_free = test::outageHorizontalRms(fgo_free, d);
  const double b_aid = test::outageHorizontalRms(fgo, d);
  const double w_free = test::outageHorizontalRms(win_free, d);
  const double w_aid = test::outageHorizontalRms(win, d);
  std::printf("outage horizontal RMS: fgo %.3f -> %.3f m, fgo-window %.3f -> %.3f m\n", b_free,
              b_aid, w_free, w_aid);
  EXPECT_LT(b_aid, 0.5 * b_free);
  EXPECT_LT(w_aid, 0.25 * w_free);
  EXPECT_GT(rep.vehicle_factors, 300);
  EXPECT_EQ(fgo.vehicle_used, rep.vehicle_factors);
  ASSERT_EQ(fgo.odometer_scale.size(), fgo.states.size());
  ASSERT_EQ(win.odometer_scale.size(), win.states.size());
  EXPECT_TRUE(fgo_free.odometer_scale.empty());
  // Without compute_covariance the scale has no sigma (NaN); 210 ppm is 3 sigma of the RTS
  // smoother's scale on the same data (filters/tests/test_vehicle_aiding.cpp: +- 68 ppm).
  const double k = fgo.odometer_scale.back(), kw = win.odometer_scale.back();
  std::printf("odometer scale: fgo %.0f ppm, fgo-window %.0f ppm (true %.0f)\n", k * 1e6, kw * 1e6,
              test::kVehicleDriveScaleError * 1e6);
  EXPECT_TRUE(std::isnan(fgo.odometer_scale_std.back()));
  EXPECT_LT(std::abs(k - test::kVehicleDriveScaleError), 210e-6);
  EXPECT_LT(std::abs(kw - test::kVehicleDriveScaleError), 210e-6);
}

TEST(VehicleAidingGraph, NhcAloneRunsInBothAndAddsNoScale) {
  test::VehicleDrive d = test::makeVehicleDrive();
  test::enableVehicleAiding(&d.problem, false, true);
  d.problem.aiding.nhc.rate_hz = 2.0;  // nodes every 0.5 s
  FgoReport rep;
  const NavSolution win = solveWindowFgo(d.problem, FgoOptions{}, &rep);
  EXPECT_TRUE(win.odometer_scale.empty());
  EXPECT_GT(rep.vehicle_factors, 600);
  const NavSolution fgo = solveBatchFgo(d.problem, FgoOptions{});
  EXPECT_LT(test::outageHorizontalRms(fgo, d), 5.0);
}

}  // namespace
}  // namespace graftnav
