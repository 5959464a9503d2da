#include <gtest/gtest.h>

#include <cmath>

#include "ekf_scenario.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/filters/rts_smoother.h"

namespace graftnav {
namespace {

using namespace ekf;

EstimationProblem makeProblem(const test::Scenario& sc, const ImuProfile& p,
                              const test::InjectedErrors& e, unsigned seed, double gnss_sigma) {
  EstimationProblem pr;
  pr.imu = test::corrupt(sc.ideal, e, p, seed);
  pr.lever_arm_b_m = Eigen::Vector3d(0.6, -0.3, -1.2);
  pr.gnss = test::makeGnss(sc.truth, pr.lever_arm_b_m, 200, gnss_sigma, seed + 1);
  pr.initial = sc.initial;
  pr.imu_profile = p;
  return pr;
}

TEST(Ekf, RecoversInjectedMemsBiasesWithinThreeSigmaAndTracksGnssNoise) {
  const test::Scenario sc = test::makeDrive(600.0, 200.0);
  const ImuProfile p = test::memsProfile();
  test::InjectedErrors e;
  e.gyro_bias_rad_s = Eigen::Vector3d(8.0, -6.0, 5.0) * kDegToRad / 3600.0;
  e.accel_bias_m_s2 = Eigen::Vector3d(0.8, -0.6, 0.5) * 1e-3 * 9.80665;
  e.gyro_scale = Eigen::Vector3d(500, -400, 800) * 1e-6;
  e.accel_scale = Eigen::Vector3d(-600, 700, 300) * 1e-6;
  const EstimationProblem pr = makeProblem(sc, p, e, 11, 0.02);

  EkfOptions opt;
  GnssInsEkf f(pr.initial, initialCovariance(pr, opt), p, opt);
  size_t gi = 0;
  for (const ImuSample& s : pr.imu) {
    f.propagate(s);
    while (gi < pr.gnss.size() && pr.gnss[gi].t_s <= s.t_s + 1e-6)
      f.updatePosition(pr.gnss[gi++], pr.lever_arm_b_m);
  }
  f.flushCovariance();
  const ErrorCov& P = f.covariance();
  for (int i = 0; i < 3; ++i) {
    const double sg = std::sqrt(P(kGyroBias + i, kGyroBias + i));
    const double sa = std::sqrt(P(kAccelBias + i, kAccelBias + i));
    EXPECT_NEAR(f.sensors().gyro_bias_rad_s[i], e.gyro_bias_rad_s[i], 3.0 * sg) << "gyro " << i;
    EXPECT_NEAR(f.sensors().accel_bias_m_s2[i], e.accel_bias_m_s2[i], 3.0 * sa) << "accel " << i;
    // And the estimate is informative: sigma well below the injected magnitude.
    EXPECT_LT(sg, 0.5 * std::abs(e.gyro_bias_rad_s[i])) << i;
  }
  // (The vertical accel bias is not asserted informative: with f_z ~ -g it trades off against
  // the z scale factor, 1000 ppm * g ~ 1 mg.)

  // The whole run through runEkf: position at the GNSS noise level with continuous GNSS.
  const NavSolution sol = runEkf(pr, opt);
  // A 99.9 % gate rejects ~0.1 % of good fixes: 0.6 expected out of 600.
  EXPECT_LE(sol.gnss_rejected, 3);
  EXPECT_EQ(sol.gnss_used + sol.gnss_rejected, static_cast<int>(pr.gnss.size()));
  NavSolution tail = sol;  // skip the first 60 s of convergence
  tail.states.erase(tail.states.begin(), tail.states.begin() + 60 * 200);
  tail.sigma.clear();
  const Evaluation ev = evaluateSolution(tail, sc.truth, {});
  EXPECT_LT(ev.overall_rms.horizontal_m, 0.03);  // GNSS noise: 0.028 m horizontal
  EXPECT_LT(ev.overall_rms.vertical_m, 0.03);
  EXPECT_LT(ev.overall_rms.heading_rad, 0.1 * kDegToRad);
}

TEST(Ekf, GnssBetweenImuSamplesIsUpdatedAtItsOwnTime) {
  const test::Scenario sc = test::makeDrive(200.0, 200.0);
  const ImuProfile p = test::tacticalProfile();
  EstimationProblem pr = makeProblem(sc, p, {}, 3, 0.01);
  // Move every fix 2.3 ms later (inside the next IMU interval) with the truth interpolated there.
  for (GnssFix& g : pr.gnss) {
    const double t = g.t_s + 0.0023;
    auto lo = std::lower_bound(sc.truth.begin(), sc.truth.end(), g.t_s,
                               [](const NavState& s, double x) { return s.t_s < x; });
    const NavState& a = *lo;
    const NavState& b = *(lo + 1);
    const double u = (t - a.t_s) / (b.t_s - a.t_s);
    NavState m = a;
    m.pos.lat_rad += u * (b.pos.lat_rad - a.pos.lat_rad);
    m.pos.lon_rad += u * (b.pos.lon_rad - a.pos.lon_rad);
    m.pos.h_m += u * (b.pos.h_m - a.pos.h_m);
    m.q_nb = a.q_nb.slerp(u, b.q_nb);
    g.t_s = t;
    g.pos = antennaPosition(m, pr.lever_arm_b_m);
    g.std_ned_m.setConstant(0.002);
  }
  const NavSolution sol = runEkf(pr, EkfOptions{});
  const Evaluation ev = evaluateSolution(sol, sc.truth, {});
  // At 10 m/s a 2.3 ms timing error would be 2.3 cm; noise-free fixes at the right time give mm.
  EXPECT_LT(ev.overall_rms.horizontal_m, 0.008);
}

TEST(Ekf, GateRejectsAnOutlierAndReportsIt) {
  const test::Scenario sc = test::makeDrive(120.0, 200.0);
  EstimationProblem pr = makeProblem(sc, test::tacticalProfile(), {}, 5, 0.02);
  pr.gnss[80].pos = earth::offsetByNed(pr.gnss[80].pos, {30.0, -20.0, 5.0});
  EkfOptions opt;
  const NavSolution sol = runEkf(pr, opt);
  EXPECT_EQ(sol.gnss_rejected, 1);
  EXPECT_EQ(sol.gnss_used, static_cast<int>(pr.gnss.size()) - 1);
  const Evaluation ev = evaluateSolution(sol, sc.truth, {});
  EXPECT_LT(ev.overall_rms.horizontal_m, 0.1);
  opt.gate_probability = 0.0;  // no gate: the outlier pulls the solution
  const NavSolution bad = runEkf(pr, opt);
  EXPECT_EQ(bad.gnss_rejected, 0);
  double worst = 0.0;
  for (const EpochError& x : evaluateSolution(bad, sc.truth, {}).epochs)
    worst = std::max(worst, x.pos_ned_m.head<2>().norm());
  EXPECT_GT(worst, 1.0);
}

TEST(Ekf, OutagesWithholdGnssAndRtsBeatsForwardInsideThem) {
  const test::Scenario sc = test::makeDrive(400.0, 200.0);
  const ImuProfile p = test::memsProfile();
  test::InjectedErrors e;
  e.gyro_bias_rad_s = Eigen::Vector3d(6.0, -8.0, 7.0) * kDegToRad / 3600.0;
  e.accel_bias_m_s2 = Eigen::Vector3d(-0.7, 0.9, 0.4) * 1e-3 * 9.80665;
  EstimationProblem pr = makeProblem(sc, p, e, 21, 0.02);
  OutageScheduleConfig oc;
  oc.start_s = 120.0;
  oc.period_s = 120.0;
  oc.length_s = 60.0;
  pr.outages = buildOutageWindows(oc, sc.initial.t_s, sc.truth.back().t_s);
  ASSERT_EQ(pr.outages.size(), 2u);
  NavSolution fwd;
  RtsStats stats;
  const NavSolution rts = runRts(pr, EkfOptions{}, &fwd, &stats);
  EXPECT_EQ(fwd.gnss_withheld, 2 * 61);  // fixes at whole seconds, both ends inclusive
  ASSERT_EQ(rts.states.size(), fwd.states.size());
  EXPECT_NEAR(rts.states.back().t_s, fwd.states.back().t_s, 1e-9);
  EXPECT_GT(stats.records, 200u);
  const Evaluation ef = evaluateSolution(fwd, sc.truth, pr.outages);
  const Evaluation er = evaluateSolution(rts, sc.truth, pr.outages);
  EXPECT_GT(ef.outage_rms.horizontal_m, 0.3);  // the MEMS drifts noticeably in 60 s
  EXPECT_LT(er.outage_rms.horizontal_m, 0.5 * ef.outage_rms.horizontal_m);
  EXPECT_LT(er.outage_rms.heading_rad, ef.outage_rms.heading_rad);
  // The smoothed solution stays continuous at the IMU rate: no jump above 1 cm per sample
  // beyond the motion itself.
  double max_jump = 0.0;
  for (size_t k = 1; k < rts.states.size(); ++k) {
    const Eigen::Vector3d d = positionErrorNed(rts.states[k].pos, rts.states[k - 1].pos);
    const Eigen::Vector3d v = 0.5 * (rts.states[k].v_n + rts.states[k - 1].v_n) * 0.005;
    max_jump = std::max(max_jump, (d - v).norm());
  }
  EXPECT_LT(max_jump, 0.01);
}

// Monte-Carlo NEES: errors drawn from the filter's own model (initial errors from P0, biases and
// scale factors as Gauss-Markov processes of the profile: with constant biases instead, the
// modelled bias random walk makes the filter measurably pessimistic, NEES ~5.6 for MEMS), NEES
// sampled at well separated epochs (end of each outage and of the run).
void neesCheck(const ImuProfile& p, int runs, bool smoothed = false) {
  const test::Scenario sc = test::makeDrive(240.0, 100.0);
  std::mt19937_64 rng(99);
  std::normal_distribution<double> nd(0.0, 1.0);
  OutageScheduleConfig oc;
  oc.start_s = 90.0;
  oc.period_s = 90.0;
  oc.length_s = 45.0;
  double sum = 0.0;
  int n = 0;
  for (int r = 0; r < runs; ++r) {
    test::InjectedErrors e;
    for (int i = 0; i < 3; ++i) {
      e.gyro_bias_rad_s[i] = p.gyro_bias_instability_rad_s * nd(rng);
      e.accel_bias_m_s2[i] = p.accel_bias_instability_m_s2 * nd(rng);
      e.gyro_scale[i] = p.gyro_scale_std * nd(rng);
      e.accel_scale[i] = p.accel_scale_std * nd(rng);
    }
    EstimationProblem pr;
    pr.imu = test::corrupt(sc.ideal, e, p, 1000 + r, /*gauss_markov=*/true);
    pr.lever_arm_b_m = Eigen::Vector3d(0.5, 0.0, -1.0);
    pr.gnss = test::makeGnss(sc.truth, pr.lever_arm_b_m, 100, 0.05, 2000 + r);
    pr.imu_profile = p;
    pr.outages = buildOutageWindows(oc, sc.initial.t_s, sc.truth.back().t_s);
    // Initial error drawn from the initial covariance.
    EkfOptions opt;
    const ErrorCov P0 = initialCovariance(pr, opt);
    ErrorState x0 = ErrorState::Zero();
    for (int i = 0; i < 9; ++i) x0[i] = std::sqrt(P0(i, i)) * nd(rng);
    pr.initial = perturbNavState(sc.initial, x0);
    pr.initial.t_s = sc.initial.t_s;
    const NavSolution sol = smoothed ? runRts(pr, opt) : runEkf(pr, opt);
    EvaluationOptions eo;
    eo.nees_interval_s = 0.0;
    const Evaluation ev = evaluateSolution(sol, sc.truth, pr.outages, eo);
    // Samples: the last epoch of each outage and the last epoch of the run.
    std::vector<double> times;
    for (const TimeWindow& w : pr.outages)
      times.push_back(smoothed ? 0.5 * (w.start_s + w.end_s) : w.end_s - 0.5);
    times.push_back(sc.truth.back().t_s);
    for (double t : times) {
      auto it = std::lower_bound(ev.epochs.begin(), ev.epochs.end(), t - 1e-6,
                                 [](const EpochError& a, double x) { return a.t_s < x; });
      ASSERT_NE(it, ev.epochs.end());
      sum += it->nees;
      ++n;
    }
  }
  const double mean = sum / n;
  ::testing::Test::RecordProperty("nees_mean", std::to_string(mean));
  const double lo = chiSquareQuantile(0.025, 9.0 * n) / n,
               hi = chiSquareQuantile(0.975, 9.0 * n) / n;
  EXPECT_GT(mean, lo) << (smoothed ? "RTS " : "EKF ") << imuGradeName(p.grade) << " NEES " << mean
                      << " band [" << lo << ", " << hi << "]";
  EXPECT_LT(mean, hi) << imuGradeName(p.grade) << " NEES " << mean << " band [" << lo << ", " << hi
                      << "]";
}

TEST(Ekf, NeesInsideChiSquareBandTactical) { neesCheck(test::tacticalProfile(), 12); }
TEST(Ekf, NeesInsideChiSquareBandMems) { neesCheck(test::memsProfile(), 12); }
// The smoother's covariance: NEES at the middle of each outage (its worst point).
TEST(Ekf, RtsNeesInsideChiSquareBandMems) { neesCheck(test::memsProfile(), 12, true); }
TEST(Ekf, ImuSampleSliceKeepsTheIncrementRate) {
  ImuSample s;
  s.t_s = 10.0;
  s.dt_s = 0.01;
  s.dtheta_rad = {0.01, 0.02, 0.03};
  s.dvel_m_s = {0.1, 0.2, 0.3};
  const ImuSample a = sliceImuSample(s, 9.99, 9.9925), b = sliceImuSample(s, 9.9925, 10.0);
  EXPECT_NEAR(a.dt_s, 0.0025, 1e-12);
  EXPECT_NEAR(a.t_s, 9.9925, 1e-12);
  EXPECT_NEAR((a.dtheta_rad + b.dtheta_rad - s.dtheta_rad).norm(), 0.0, 1e-15);
  EXPECT_NEAR((a.dvel_m_s - 0.25 * s.dvel_m_s).norm(), 0.0, 1e-13);
}

TEST(Ekf, InvalidOptionsAreRejected) {
  EkfOptions o;
  o.covariance_interval_s = 0.0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = EkfOptions{};
  o.output_decimation = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
