// Every estimator on GNSS with real timing: 20 Hz fixes, a jittered 5 Hz stream with fixes
// between IMU samples, fixes 1 ms apart and duplicate stamps, and a first fix right after the
// initial state. The factor graphs' node layout never makes an interval of fewer than two IMU
// samples (a one-sample preintegration cannot be inverted), and no fix is dropped for it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "graftnav/filters/ekf.h"
#include "graftnav/filters/rts_smoother.h"
#include "graftnav/graph/fgo_solver.h"
#include "graftnav/graph/node_layout.h"
#include "graph_scenario.h"

namespace graftnav {
namespace {

constexpr double kRate_hz = 100.0;

struct TimingCase {
  test::Scenario sc;
  EstimationProblem problem;
};

// A 40-s drive at 100 Hz, MEMS-like errors, RTK-grade fixes (2 cm) at the given times (antenna
// positions from the truth interpolated to each fix time).
TimingCase makeCase(const std::vector<double>& fix_offsets_s) {
  TimingCase c;
  c.sc = test::makeScenario(40.0, kRate_hz, 10.0);
  test::ImuErrors err;
  err.bg_rad_s << 4e-5, -3e-5, 5e-5;
  err.ba_m_s2 << 8e-3, -6e-3, 5e-3;
  err.arw_rad_sqrt_s = 4.4e-5;
  err.vrw_m_s_sqrt_s = 1e-3;
  EstimationProblem& p = c.problem;
  p.imu = test::addImuErrors(c.sc.ideal, err, 11);
  p.lever_arm_b_m << 0.2, 0.1, -1.0;
  p.initial = c.sc.truth.front();
  p.imu_profile.arw_rad_sqrt_s = err.arw_rad_sqrt_s;
  p.imu_profile.vrw_m_s_sqrt_s = err.vrw_m_s_sqrt_s;
  p.imu_profile.gyro_bias_instability_rad_s = 5e-5;
  p.imu_profile.accel_bias_instability_m_s2 = 1e-2;
  p.initial_sigma << 0.05, 0.05, 0.05, 0.02, 0.02, 0.02, 1e-3, 1e-3, 5e-3;
  std::mt19937 rng(12);
  std::normal_distribution<double> nd(0.0, 0.02);
  const double t0 = p.initial.t_s;
  for (double off : fix_offsets_s) {
    const double t = t0 + off;
    const double u = off * kRate_hz;  // truth[k] is at t0 + k / rate
    const auto k = std::min(static_cast<size_t>(u), c.sc.truth.size() - 2);
    const double w = u - static_cast<double>(k);
    const NavState& a = c.sc.truth[k];
    const NavState& b = c.sc.truth[k + 1];
    const Eigen::Vector3d d = earth::nedFromGeodetic(a.pos, b.pos);
    GnssFix f;
    f.t_s = t;
    const Eigen::Vector3d ant = a.q_nb * p.lever_arm_b_m;
    f.pos = earth::offsetByNed(a.pos, w * d + ant + Eigen::Vector3d(nd(rng), nd(rng), nd(rng)));
    f.std_ned_m.setConstant(0.02);
    f.fix_type = 4;
    p.gnss.push_back(f);
  }
  return c;
}

std::vector<double> regular(double period_s, double first_s) {
  std::vector<double> t;
  for (double x = first_s; x < 39.99; x += period_s) t.push_back(x);
  return t;
}

// RMS horizontal position error of a solution against the truth (every epoch).
double horizontalRms(const NavSolution& sol, const test::Scenario& sc) {
  double s = 0.0;
  int n = 0;
  for (const NavState& st : sol.states) {
    const double u = (st.t_s - sc.truth.front().t_s) * kRate_hz;
    const auto k = static_cast<size_t>(std::llround(u));
    if (k >= sc.truth.size() || std::abs(u - static_cast<double>(k)) > 1e-6) continue;
    const Eigen::Vector3d d = earth::nedFromGeodetic(sc.truth[k].pos, st.pos);
    s += d.head<2>().squaredNorm();
    ++n;
  }
  EXPECT_GT(n, 1000);
  return std::sqrt(s / std::max(n, 1));
}

// The layout's intervals all hold at least two samples and every usable fix sits on a node.
void expectLayoutSound(const EstimationProblem& p, const std::string& what) {
  FgoOptions o;
  const LocalFrame frame(p.initial.pos);
  const NodeLayout L = buildNodeLayout(p, frame, o, seriesPass(p.imu));
  size_t on_nodes = 0;
  for (size_t k = 0; k < L.nodes.size(); ++k) {
    on_nodes += L.nodes[k].gnss.size();
    if (k + 1 < L.nodes.size()) {
      EXPECT_GE(L.nodes[k + 1].sample_end, L.nodes[k].sample_end + 2)
          << what << ": interval " << k << " at t=" << L.nodes[k].t_s;
    }
  }
  size_t usable = 0;
  for (const GnssFix& f : p.gnss) usable += f.t_s > p.initial.t_s + 1e-6;
  EXPECT_EQ(L.fixes.size(), usable) << what;
  EXPECT_EQ(on_nodes, usable) << what;
  for (const GnssObservation& obs : L.fixes)
    EXPECT_LT(std::abs(obs.dt_s), 2.0 / kRate_hz) << what << " fix at " << obs.fix.t_s;
}

// Runs ekf, rts, fgo and fgo-window; each must finish with a finite solution within `tol_m`
// horizontal RMS of the truth, using every fix.
void expectEveryEstimatorRuns(const TimingCase& c, double tol_m, const std::string& what) {
  expectLayoutSound(c.problem, what);
  const int fixes = static_cast<int>(c.problem.gnss.size());
  const NavSolution ekf = runEkf(c.problem, EkfOptions{});
  EXPECT_LT(horizontalRms(ekf, c.sc), tol_m) << what << " ekf";
  EXPECT_EQ(ekf.gnss_used + ekf.gnss_rejected, fixes) << what << " ekf";
  const NavSolution rts = runRts(c.problem, EkfOptions{});
  EXPECT_LT(horizontalRms(rts, c.sc), tol_m) << what << " rts";
  FgoReport rep;
  NavSolution fgo;
  ASSERT_NO_THROW(fgo = solveBatchFgo(c.problem, FgoOptions{}, &rep)) << what;
  EXPECT_EQ(rep.gnss_factors, fixes) << what << " fgo";
  EXPECT_LT(horizontalRms(fgo, c.sc), tol_m) << what << " fgo";
  NavSolution win;
  ASSERT_NO_THROW(win = solveWindowFgo(c.problem, FgoOptions{})) << what;
  EXPECT_LT(horizontalRms(win, c.sc), tol_m) << what << " fgo-window";
  for (const NavSolution* s : std::vector<const NavSolution*>{&ekf, &rts, &fgo, &win}) {
    for (const NavState& st : s->states) {
      ASSERT_TRUE(std::isfinite(st.pos.lat_rad) && st.v_n.allFinite()) << what << s->estimator;
    }
  }
}

TEST(GnssTiming, TwentyHertzFixesRunInEveryEstimator) {
  expectEveryEstimatorRuns(makeCase(regular(0.05, 0.05)), 0.05, "20 Hz");
}

TEST(GnssTiming, JitteredFiveHertzBetweenSamplesRunsInEveryEstimator) {
  std::vector<double> t = regular(0.2, 0.2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  for (double& x : t) x += jitter(rng) + 0.0037;  // off the sample ends, +-20 ms
  std::sort(t.begin(), t.end());
  expectEveryEstimatorRuns(makeCase(t), 0.05, "jittered 5 Hz");
}

TEST(GnssTiming, FixesOneMillisecondApartAndDuplicateStampsRunInEveryEstimator) {
  std::vector<double> t;
  t.push_back(0.001);  // within a sample of the initial state
  for (double x : regular(1.0, 1.0)) {
    t.push_back(x);
    t.push_back(x + 0.001);  // 1 ms later: between the same two samples
  }
  t.push_back(20.5);
  t.push_back(20.5);    // a duplicate stamp
  t.push_back(39.991);  // on the second-to-last sample: a one-sample tail after it
  std::sort(t.begin(), t.end());
  expectEveryEstimatorRuns(makeCase(t), 0.05, "1 ms apart");
}

TEST(GnssTiming, FixesOnConsecutiveSamplesShareANode) {
  // 100 Hz fixes on a 100 Hz IMU: every other fix would be one sample after the one before.
  const TimingCase c = makeCase(regular(0.01, 0.01));
  expectLayoutSound(c.problem, "100 Hz");
  NavSolution win;
  ASSERT_NO_THROW(win = solveWindowFgo(c.problem, FgoOptions{}));
  EXPECT_LT(horizontalRms(win, c.sc), 0.05);
}

}  // namespace
}  // namespace graftnav
