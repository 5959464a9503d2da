// The sliding window that places its nodes during its own pass over the IMU (one read) against
// the window over a layout placed in a pass beforehand: the same nodes, every value equal to the
// last bit; and the one-pass graph holds only the window's nodes at the end.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/fgo_solver.h"
#include "graftnav/graph/sliding_window.h"
#include "graph_scenario.h"

namespace graftnav {
namespace {

// Every node's value as it entered the window.
class Entered final : public WindowListener {
 public:
  void entered(size_t k, const NodeValue& x, const ImuSampleBuffer&) override {
    EXPECT_EQ(k, values.size());
    values.push_back(x);
  }
  std::vector<NodeValue> values;
};

EstimationProblem outageProblem() {
  const test::Scenario sc = test::makeScenario(60.0, 100.0, 10.0);
  EstimationProblem p;
  p.imu = sc.ideal;
  p.initial = sc.truth.front();
  p.gnss = test::makeGnss(sc, Eigen::Vector3d::Zero(), 1.0, 0.02, 3);
  for (GnssFix& f : p.gnss) f.t_s += 0.0013;  // between sample ends
  p.outages.push_back(TimeWindow{p.initial.t_s + 20.0, p.initial.t_s + 35.0});
  p.imu_profile.arw_rad_sqrt_s = 1e-4;
  p.imu_profile.vrw_m_s_sqrt_s = 1e-3;
  return p;
}

TEST(WindowOnePass, EqualsTheWindowOverAPlacedLayout) {
  const EstimationProblem p = outageProblem();
  FgoOptions o;
  o.window_nodes = 5;
  FgoGraph placed(p, o, seriesPass(p.imu));
  FgoGraph growing(p, o, PlaceNodesDuringPass{});
  EXPECT_TRUE(growing.placing());
  EXPECT_EQ(growing.nodeCount(), 0u);
  Entered a, b;
  runSlidingWindow(placed, seriesPass(p.imu), nullptr, false, &a);
  runSlidingWindow(growing, seriesPass(p.imu), nullptr, false, &b);
  EXPECT_FALSE(growing.placing());
  ASSERT_GT(placed.nodeCount(), 60u);
  EXPECT_EQ(growing.nodeCount(), placed.nodeCount());
  EXPECT_EQ(growing.fixCount(), placed.fixCount());
  EXPECT_EQ(growing.gnssWithheld(), placed.gnssWithheld());
  EXPECT_GT(growing.gnssWithheld(), 10);
  EXPECT_EQ(growing.sampleCount(), p.imu.size());
  ASSERT_EQ(b.values.size(), a.values.size());
  for (size_t k = 0; k < a.values.size(); ++k) {
    EXPECT_EQ(b.values[k].p_w, a.values[k].p_w) << k;
    EXPECT_EQ(b.values[k].v_w, a.values[k].v_w) << k;
    EXPECT_EQ(b.values[k].q_wb.coeffs(), a.values[k].q_wb.coeffs()) << k;
    EXPECT_EQ(b.values[k].ba, a.values[k].ba) << k;
  }
  // Only the window's nodes are left; the ones before are forgotten.
  const size_t n = growing.nodeCount();
  EXPECT_NO_THROW(growing.node(n - static_cast<size_t>(o.window_nodes)));
  EXPECT_THROW(growing.node(0), std::out_of_range);
  EXPECT_THROW(growing.node(n - static_cast<size_t>(o.window_nodes) - 1), std::out_of_range);
  EXPECT_THROW(growing.fix(0), std::out_of_range);
}

TEST(WindowOnePass, KeepsEveryNodeForTheBatch) {
  const EstimationProblem p = outageProblem();
  FgoGraph growing(p, FgoOptions{}, PlaceNodesDuringPass{});
  runSlidingWindow(growing, seriesPass(p.imu), nullptr, true);
  EXPECT_NO_THROW(growing.node(0));
  EXPECT_NO_THROW(growing.fix(0));
  EXPECT_TRUE(growing.hasPreintegration(0));
}

TEST(WindowOnePass, TooFewSamplesIsAnError) {
  EstimationProblem p = outageProblem();
  p.initial.t_s = p.imu.back().t_s + 1.0;  // after the last sample: no node 0
  FgoGraph growing(p, FgoOptions{}, PlaceNodesDuringPass{});
  EXPECT_THROW(runSlidingWindow(growing, seriesPass(p.imu), nullptr, false), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
