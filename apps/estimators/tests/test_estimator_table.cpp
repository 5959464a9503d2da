// The assembled table: every estimator of filters/ and graph/ by name, with the streamed forms
// and the scale-factor, GNSS and smoothed-filter fields the commands rely on, each entry running
// its own estimator.
#include <gtest/gtest.h>

#include <algorithm>

#include "ekf_scenario.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/graph/fgo_solver.h"

namespace graftnav {
namespace {

TEST(EstimatorTable, HoldsEveryEstimatorOnceWithItsForms) {
  const EstimatorRegistry& t = estimatorTable();
  std::vector<std::string> names = t.names();
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"ekf", "fgo", "fgo-window", "free-inertial", "rts"}));
  for (const char* n : {"ekf", "rts", "fgo", "fgo-window"}) EXPECT_TRUE(t.canStream(n)) << n;
  EXPECT_FALSE(t.canStream("free-inertial"));
  EXPECT_TRUE(t.find("ekf").estimates_scale_factors);
  EXPECT_TRUE(t.find("rts").estimates_scale_factors);
  EXPECT_FALSE(t.find("fgo").estimates_scale_factors);
  EXPECT_FALSE(t.find("fgo-window").estimates_scale_factors);
  EXPECT_EQ(&t, &estimatorTable());  // built once
}

TEST(EstimatorTable, SaysWhichEstimatorTakesNoGnssAndWhichSmoothsAFilter) {
  const EstimatorRegistry& t = estimatorTable();
  for (const auto& e : t.entries()) {
    EXPECT_EQ(e.uses_gnss, e.name != "free-inertial") << e.name;
    if (e.name == "rts") {
      EXPECT_EQ(e.smooths, "ekf");
    } else {
      EXPECT_TRUE(e.smooths.empty()) << e.name;
    }
  }
  EXPECT_TRUE(t.contains(t.find("rts").smooths));
}

TEST(EstimatorTable, UnknownNameListsTheKnownOnes) {
  try {
    estimatorTable().find("ukf");
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown estimator 'ukf'"), std::string::npos) << what;
    EXPECT_NE(what.find("fgo-window"), std::string::npos) << what;
  }
}

// The table's entries are the estimators themselves: the same epochs as calling them directly.
TEST(EstimatorTable, EntriesRunTheirOwnEstimator) {
  const test::Scenario sc = test::makeDrive(120.0, 100.0);
  EstimationProblem p;
  p.imu = sc.ideal;
  p.initial = sc.initial;
  p.imu_profile = test::memsProfile();
  for (std::size_t k = 100; k < sc.truth.size(); k += 100) {
    GnssFix f;
    f.t_s = sc.truth[k].t_s;
    f.pos = sc.truth[k].pos;
    f.std_ned_m = Eigen::Vector3d::Constant(0.05);
    p.gnss.push_back(f);
  }
  EstimatorOptions o;
  const NavSolution a = estimatorTable().run("ekf", p, o);
  const NavSolution b = runEkf(p, o.ekf);
  ASSERT_EQ(a.states.size(), b.states.size());
  EXPECT_EQ(a.states.back().pos.lat_rad, b.states.back().pos.lat_rad);
  EXPECT_EQ(a.gnss_used, b.gnss_used);
  const NavSolution g = estimatorTable().run("fgo", p, o);
  const NavSolution h = solveBatchFgo(p, o.fgo);
  ASSERT_EQ(g.states.size(), h.states.size());
  EXPECT_EQ(g.states.back().pos.lon_rad, h.states.back().pos.lon_rad);
}

}  // namespace
}  // namespace graftnav
