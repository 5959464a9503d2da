// The filter-against-smoother cross-check: with errors drawn as a forward filter and its smoother
// make them, the filter-smoother form gives normalized differences of RMS 1 and the sum form
// understates them; a real disagreement is found where it is.
#include "graftnav/eval/cross_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

struct Pair {
  NavSolution filter, smoother;
  std::vector<TimeWindow> outages{{100.0, 160.0}, {300.0, 360.0}};
};

// At rest at one place, 10 Hz for 500 s. Smoother error e_s ~ N(0, p_s); the filter's error is
// e_s + w with w ~ N(0, q_w) independent of e_s, as for a forward filter and its RTS smoother.
Pair makePair(double p_s, double q_w, unsigned seed, double smoother_bias_m = 0.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Geodetic origin{0.5, 2.0, 100.0};
  Pair p;
  for (int k = 0; k <= 5000; ++k) {
    const double t = 0.1 * k;
    Eigen::Vector4d e_s, w;  // north, east, down (m), heading (rad)
    for (int i = 0; i < 4; ++i) {
      const double scale = i == 3 ? 1e-3 : 1.0;
      e_s[i] = std::sqrt(p_s) * scale * n01(rng);
      w[i] = std::sqrt(q_w) * scale * n01(rng);
    }
    auto state = [&](const Eigen::Vector4d& e) {
      NavState s;
      s.t_s = t;
      s.pos = earth::offsetByNed(origin, e.head<3>());
      s.q_nb = quatFromEuler(Eigen::Vector3d(0.0, 0.0, 1.0 + e[3]));
      return s;
    };
    auto sigma = [](double var) {
      PvaSigma s = PvaSigma::Constant(std::sqrt(var));
      s.tail<3>() *= 1e-3;  // attitude in rad, as drawn
      return s;
    };
    p.filter.states.push_back(state(e_s + w));
    p.filter.sigma.push_back(sigma(p_s + q_w));
    Eigen::Vector4d e_b = e_s;
    if (t >= 300.0 && t <= 360.0) e_b[0] += smoother_bias_m;  // the smoother alone is off
    p.smoother.states.push_back(state(e_b));
    p.smoother.sigma.push_back(sigma(p_s));
  }
  return p;
}

TEST(CrossCheck, FilterAgainstItsSmootherIsNormalizedByTheDifferenceOfTheCovariances) {
  const Pair p = makePair(4.0, 1.0, 7);
  const CrossCheck c =
      crossCheck(p.filter, p.smoother, p.outages, DifferenceCovariance::kFilterSmoother);
  ASSERT_TRUE(c.has_sigma);
  EXPECT_EQ(c.horizontal.epochs, 2 * 601);
  EXPECT_EQ(c.horizontal.normalized_epochs, c.horizontal.epochs);
  for (const CrossCheckStat* s : {&c.horizontal, &c.vertical, &c.heading})
    EXPECT_NEAR(s->rms_normalized, 1.0, 0.06);
  EXPECT_NEAR(c.horizontal.rms_sigma, std::sqrt(2.0), 1e-9);  // sqrt(var_N + var_E), q_w = 1
  EXPECT_NEAR(c.horizontal.rms_difference, std::sqrt(2.0), 0.1);
  EXPECT_LT(c.maxNormalized(), 5.0);
  EXPECT_GT(c.maxNormalized(), 2.0);

  // The sum of the variances is an upper bound: the same differences look 3x smaller
  // (sqrt(q_w / (2 p_s + q_w)) = 1/3), the agreement over-stated.
  const CrossCheck u =
      crossCheck(p.filter, p.smoother, p.outages, DifferenceCovariance::kIndependent);
  EXPECT_NEAR(u.horizontal.rms_normalized, 1.0 / 3.0, 0.03);
  EXPECT_NEAR(u.vertical.rms_normalized, 1.0 / 3.0, 0.03);
}

TEST(CrossCheck, ADisagreementInOneOutageIsFoundThere) {
  const Pair p = makePair(4.0, 1.0, 11, 8.0);  // smoother 8 m off north in the second outage
  const CrossCheck c =
      crossCheck(p.filter, p.smoother, p.outages, DifferenceCovariance::kFilterSmoother);
  EXPECT_GT(c.horizontal.max_normalized, 3.0);
  EXPECT_GE(c.horizontal.max_normalized_t_s, 300.0);
  EXPECT_LE(c.horizontal.max_normalized_t_s, 360.0);
  EXPECT_LT(c.vertical.max_normalized, 5.0);  // the other components still agree
  EXPECT_EQ(c.maxNormalized(), c.horizontal.max_normalized);
}

TEST(CrossCheck, WithoutSigmasOnlyTheDifferencesAreGiven) {
  Pair p = makePair(4.0, 1.0, 3);
  p.smoother.sigma.clear();
  const CrossCheck c =
      crossCheck(p.filter, p.smoother, p.outages, DifferenceCovariance::kIndependent);
  EXPECT_FALSE(c.has_sigma);
  EXPECT_EQ(c.horizontal.epochs, 2 * 601);
  EXPECT_EQ(c.horizontal.normalized_epochs, 0);
  EXPECT_TRUE(std::isfinite(c.horizontal.rms_difference));
  EXPECT_TRUE(std::isnan(c.horizontal.rms_normalized));
  EXPECT_TRUE(std::isnan(c.maxNormalized()));
  EXPECT_STREQ(differenceCovarianceName(c.form), "sum-upper-bound");
}

}  // namespace
}  // namespace graftnav
