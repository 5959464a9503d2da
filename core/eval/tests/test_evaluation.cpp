#include <gtest/gtest.h>

#include <cmath>

#include "graftnav/nav/earth.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

// Reference: moving north at 1 m/s, level, yaw 179 deg, sampled every 2 s (interpolated).
// Solution every 1 s: north error t m, down error 1 m, velocity error 1 m/s north,
// heading error 0.01 t rad (crossing +-180 deg). Outages [2,4] and [7,8].
struct Example {
  NavSeries ref;
  NavSolution sol;
  std::vector<TimeWindow> outages{{2.0, 4.0}, {7.0, 8.0}};
  Example() {
    const Geodetic origin{30.0 * kDegToRad, 114.0 * kDegToRad, 20.0};
    const double Rm = earth::radiiOfCurvature(origin.lat_rad).meridian_m + origin.h_m;
    const double yaw0 = 179.0 * kDegToRad;
    for (int t = 0; t <= 10; t += 2) {
      NavState s;
      s.t_s = t;
      s.pos = origin;
      s.pos.lat_rad += t / Rm;
      s.v_n = {1, 0, 0};
      s.q_nb = quatFromEuler({0, 0, yaw0});
      ref.push_back(s);
    }
    sol.estimator = "test";
    for (int t = 0; t <= 10; ++t) {
      NavState s;
      s.t_s = t;
      s.pos = origin;
      s.pos.lat_rad += 2.0 * t / Rm;
      s.pos.h_m -= 1.0;
      s.v_n = {2, 0, 0};
      s.q_nb = quatFromEuler({0, 0, wrapAngle(yaw0 + 0.01 * t)});
      sol.states.push_back(s);
      sol.sigma.push_back(PvaSigma::Constant(2.0));
    }
  }
};

TEST(Evaluation, HandComputedOutageStatistics) {
  Example ex;
  EvaluationOptions opt;
  opt.epochs = EvaluationEpochs::kSolution;
  const Evaluation ev = evaluateSolution(ex.sol, ex.ref, ex.outages, opt);
  ASSERT_EQ(ev.epochs.size(), 11u);
  EXPECT_NEAR(ev.epochs[5].pos_ned_m.x(), 5.0, 1e-6);
  EXPECT_NEAR(ev.epochs[5].pos_ned_m.z(), 1.0, 1e-9);
  EXPECT_NEAR(ev.epochs[5].euler_rad.z(), 0.05, 1e-9);  // wrapped across +-180 deg
  // Overall: horizontal sqrt(sum t^2 / 11) = sqrt(385/11) = sqrt(35).
  EXPECT_NEAR(ev.overall_rms.horizontal_m, std::sqrt(35.0), 1e-5);
  EXPECT_NEAR(ev.overall_rms.vertical_m, 1.0, 1e-9);
  EXPECT_NEAR(ev.overall_rms.heading_rad, 0.01 * std::sqrt(35.0), 1e-9);
  EXPECT_NEAR(ev.overall_rms.roll_rad, 0.0, 1e-9);
  // Seed statistic: outage epochs t = 2,3,4,7,8 -> sqrt((4+9+16+49+64)/5) = sqrt(28.4).
  EXPECT_EQ(ev.outage_epochs, 5);
  EXPECT_NEAR(ev.outage_rms.horizontal_m, std::sqrt(28.4), 1e-5);
  EXPECT_NEAR(ev.outage_rms.heading_rad, 0.01 * std::sqrt(28.4), 1e-9);
  // Peers' statistic: maxima 4 and 8 -> sqrt((16+64)/2) = sqrt(40).
  ASSERT_EQ(ev.outages.size(), 2u);
  EXPECT_NEAR(ev.outages[0].max.horizontal_m, 4.0, 1e-6);
  EXPECT_NEAR(ev.outages[1].max.horizontal_m, 8.0, 1e-6);
  EXPECT_NEAR(ev.outage_max_rms.horizontal_m, std::sqrt(40.0), 1e-5);
  EXPECT_NEAR(ev.outage_max_rms.vertical_m, 1.0, 1e-9);
  // NEES with sigma 2 everywhere: (t^2 (1 + 1e-4) + 1 + 1) / 4 per epoch, averaged over 11.
  EXPECT_EQ(ev.nees_samples, 11);
  EXPECT_NEAR(ev.nees_mean, (385.0 * 1.0001 + 22.0) / 44.0, 1e-4);
  EXPECT_LT(ev.nees_band_low, 9.0);
  EXPECT_GT(ev.nees_band_high, 9.0);
}

TEST(Evaluation, AutoEpochsAvoidInterpolatingASparseReferenceThroughVibration) {
  // Dense solution (50 Hz) equal to the truth, with a 5 Hz roll vibration; the reference keeps
  // every 5th epoch (10 Hz). At the reference epochs the error is zero; interpolating the
  // reference to the solution epochs invents roll errors.
  NavSolution sol;
  NavSeries ref;
  for (int k = 0; k <= 500; ++k) {
    NavState s;
    s.t_s = k * 0.02;
    s.pos = {0.5, 2.0, 10.0};
    s.q_nb = quatFromEuler({0.001 * std::sin(2 * M_PI * 5.0 * s.t_s + 0.3), 0.0, 1.0});
    sol.states.push_back(s);
    sol.sigma.push_back(PvaSigma::Constant(1.0));
    if (k % 5 == 0) ref.push_back(s);
  }
  const Evaluation a = evaluateSolution(sol, ref, {});
  EXPECT_EQ(a.epochs.size(), ref.size());
  EXPECT_LT(a.overall_rms.roll_rad, 1e-12);
  EvaluationOptions o;
  o.epochs = EvaluationEpochs::kSolution;
  const Evaluation b = evaluateSolution(sol, ref, {}, o);
  EXPECT_EQ(b.epochs.size(), sol.states.size());
  EXPECT_GT(b.overall_rms.roll_rad, 1e-4);
}

TEST(Evaluation, ChiSquareQuantilesMatchTables) {
  EXPECT_NEAR(normalQuantile(0.975), 1.959963985, 1e-7);
  EXPECT_NEAR(normalQuantile(0.001), -3.090232306, 1e-7);
  EXPECT_NEAR(chiSquareQuantile(0.999, 3), 16.266, 0.002);  // table values
  EXPECT_NEAR(chiSquareQuantile(0.95, 9), 16.919, 0.002);
  EXPECT_NEAR(chiSquareQuantile(0.5, 2), 2.0 * std::log(2.0), 1e-8);
  EXPECT_NEAR(chiSquareQuantile(0.025, 900), 818.0, 1.5);
}

TEST(Distributions, FisherUpperTailMatchesTables) {
  // Critical values from F tables: P(F > f_crit) = alpha.
  EXPECT_NEAR(fisherUpperTail(21.198, 1, 4), 0.01, 2e-5);
  EXPECT_NEAR(fisherUpperTail(4.9646, 1, 10), 0.05, 2e-5);
  EXPECT_NEAR(fisherUpperTail(3.0984, 3, 20), 0.05, 2e-5);
  EXPECT_NEAR(fisherUpperTail(4052.2, 1, 1), 0.01, 2e-5);
  // F(1, nu) = t_nu^2, and F(2, 2) has the closed form 1 / (1 + f).
  EXPECT_NEAR(fisherUpperTail(1.96 * 1.96, 1, 1e6), 0.05, 1e-4);
  EXPECT_NEAR(fisherUpperTail(3.0, 2, 2), 0.25, 1e-12);
  // Huge dof2 (a sigma "estimated" to 1e20 degrees of freedom): the chi-square limit, not the
  // incomplete beta's rounding (which gave 1.0 at f = 10).
  for (double nu : {1e8, 1e15, 1e20})
    EXPECT_NEAR(fisherUpperTail(10.0, 1, nu), std::erfc(std::sqrt(5.0)), 1e-9) << nu;
  EXPECT_NEAR(fisherUpperTail(10.0, 1, 1e6), std::erfc(std::sqrt(5.0)), 2e-5);
  EXPECT_EQ(fisherUpperTail(0.0, 1, 4), 1.0);
  EXPECT_EQ(fisherUpperTail(INFINITY, 1, 4), 0.0);
  EXPECT_THROW(fisherUpperTail(1.0, 0.0, 4), std::invalid_argument);
}

TEST(Evaluation, InterpolationIsLinearAndSlerps) {
  NavSeries s(2);
  s[0].t_s = 0;
  s[1].t_s = 1;
  s[1].pos = {0.002, 0.004, 10.0};
  s[1].v_n = {1, 2, 3};
  s[1].q_nb = quatFromEuler({0, 0, 0.4});
  const auto m = interpolateNav(s, 0.25);
  ASSERT_TRUE(m.has_value());
  EXPECT_NEAR(m->pos.lat_rad, 0.0005, 1e-15);
  EXPECT_NEAR(m->pos.h_m, 2.5, 1e-12);
  EXPECT_NEAR(m->v_n.y(), 0.5, 1e-12);
  EXPECT_NEAR(eulerFromQuat(m->q_nb).z(), 0.1, 1e-12);
  EXPECT_FALSE(interpolateNav(s, 1.5).has_value());
}

TEST(Evaluation, NonOverlappingSeriesThrow) {
  Example ex;
  for (auto& s : ex.sol.states) s.t_s += 100.0;
  EXPECT_THROW(evaluateSolution(ex.sol, ex.ref, ex.outages), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
