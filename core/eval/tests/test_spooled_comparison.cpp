// Two solutions compared from their spools give the in-memory numbers bit for bit: the pair's
// evaluation and the cross-check in both forms, with series of different rates and spans, time-
// varying sigmas, and a solution without sigmas.
#include "graftnav/eval/spooled_comparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

// A wandering solution at `rate_hz` from t0 to t1, its sigma growing and shrinking with time.
NavSolution wander(double rate_hz, double t0_s, double t1_s, unsigned seed, bool with_sigma) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Geodetic origin{0.5, 2.0, 100.0};
  NavSolution sol;
  Eigen::Vector4d e = Eigen::Vector4d::Zero();
  for (int k = 0;; ++k) {
    const double t = t0_s + k / rate_hz;
    if (t > t1_s) break;
    e += Eigen::Vector4d(0.05 * n01(rng), 0.05 * n01(rng), 0.02 * n01(rng), 1e-4 * n01(rng));
    NavState s;
    s.t_s = t;
    s.gnss_week = 2200;
    s.pos = earth::offsetByNed(origin, e.head<3>() + Eigen::Vector3d(0.5 * t, 0.1 * t, 0.0));
    s.v_n = Eigen::Vector3d(0.5, 0.1, 0.0);
    s.q_nb = quatFromEuler(Eigen::Vector3d(0.01, -0.02, 1.0 + e[3]));
    sol.states.push_back(s);
    if (with_sigma) {
      PvaSigma sg = PvaSigma::Constant(1.0 + 0.5 * std::sin(0.01 * t));
      sg.tail<3>() *= 1e-3;
      sol.sigma.push_back(sg);
    }
  }
  return sol;
}

void expectSameStat(const CrossCheckStat& a, const CrossCheckStat& b, const char* what) {
  for (auto [x, y] :
       {std::pair{a.rms_difference, b.rms_difference}, std::pair{a.rms_sigma, b.rms_sigma},
        std::pair{a.rms_normalized, b.rms_normalized},
        std::pair{a.max_normalized, b.max_normalized},
        std::pair{a.max_normalized_t_s, b.max_normalized_t_s}}) {
    if (std::isnan(x)) {
      EXPECT_TRUE(std::isnan(y)) << what;
    } else {
      EXPECT_EQ(x, y) << what;  // bit for bit
    }
  }
  EXPECT_EQ(a.epochs, b.epochs) << what;
  EXPECT_EQ(a.normalized_epochs, b.normalized_epochs) << what;
}

void expectSame(const CrossCheck& a, const CrossCheck& b) {
  EXPECT_EQ(a.has_sigma, b.has_sigma);
  EXPECT_EQ(a.form, b.form);
  expectSameStat(a.horizontal, b.horizontal, "horizontal");
  expectSameStat(a.vertical, b.vertical, "vertical");
  expectSameStat(a.heading, b.heading, "heading");
}

void spool(const NavSolution& s, SolutionSpool* out) { spoolSolution(s, out); }

TEST(SpooledComparison, SameNumbersAsInMemory) {
  const std::vector<TimeWindow> outages{{0.0, 30.0}, {100.0, 160.0}, {300.0, 390.0}};
  struct Case {
    NavSolution a, b;
  };
  const std::vector<Case> cases{
      {wander(50.0, 0.0, 400.0, 1, true), wander(50.0, 0.0, 400.0, 2, true)},
      {wander(50.0, 0.0, 400.0, 3, true), wander(10.0, 20.0, 350.0, 4, true)},  // sparser, inside
      {wander(10.0, 5.0, 400.0, 5, true), wander(50.0, 0.0, 380.0, 6, false)},  // b no sigma
  };
  for (const Case& c : cases) {
    SolutionSpool sa, sb;
    spool(c.a, &sa);
    spool(c.b, &sb);
    EXPECT_EQ(sa.size(), c.a.states.size());
    const Evaluation mem = evaluateSolution(c.a, c.b.states, outages);
    const Evaluation str = evaluatePair(sa, sb, outages);
    EXPECT_EQ(mem.outage_rms.horizontal_m, str.outage_rms.horizontal_m);
    EXPECT_EQ(mem.outage_rms.heading_rad, str.outage_rms.heading_rad);
    EXPECT_EQ(mem.outage_max_rms.vertical_m, str.outage_max_rms.vertical_m);
    EXPECT_GT(mem.outage_rms.horizontal_m, 0.0);
    for (auto form : {DifferenceCovariance::kFilterSmoother, DifferenceCovariance::kIndependent}) {
      const CrossCheck m = crossCheck(c.a, c.b, outages, form);
      expectSame(m, crossCheck(sa, sb, outages, form));
      EXPECT_GT(m.horizontal.epochs, 1000);
    }
  }
}

TEST(SpooledComparison, SpoolGivesBackWhatWasWritten) {
  const NavSolution s = wander(20.0, 0.0, 50.0, 9, true);
  SolutionSpool sp;
  spool(s, &sp);
  ASSERT_TRUE(sp.hasSigma());
  auto states = sp.states()();
  auto sigmas = sp.sigmas();
  NavState st;
  PvaSigma sg;
  for (std::size_t k = 0; k < s.states.size(); ++k) {
    ASSERT_TRUE(states->next(&st));
    ASSERT_TRUE(sigmas.next(&sg));
    EXPECT_EQ(st.pos.lat_rad, s.states[k].pos.lat_rad);
    EXPECT_EQ(st.q_nb.coeffs(), s.states[k].q_nb.coeffs());
    EXPECT_EQ(sg, s.sigma[k]);
  }
  EXPECT_FALSE(states->next(&st));
  SolutionSpool mixed;
  const PvaSigma one = PvaSigma::Ones();
  mixed.add(s.states[0], &one);
  EXPECT_THROW(mixed.add(s.states[1], nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
