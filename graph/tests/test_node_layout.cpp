// The node layout found in one streamed pass (buildNodeLayout) against a direct in-memory
// construction of the same rule (binary searches over the whole series), on a drive with an
// outage, an IMU gap, fixes before the initial state and after the last sample, fed in blocks
// of every size from 1 sample to the whole series; GNSS out of time order is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "graftnav/graph/fgo_solver.h"
#include "graftnav/graph/node_layout.h"
#include "graph_scenario.h"

namespace graftnav {
namespace {

// The layout rule over a series in memory: each fix on the sample whose end is nearest
// (dropped outside the samples' cover), nodes on those samples at least two samples apart (a fix
// nearer than that to the previous fix's sample shares its node; the first fix goes at least
// two samples after the initial state's), a last node at the last sample unless that is a
// one-sample tail, and between them every max_node_spacing_s on the nearest samples.
NodeLayout directLayout(const EstimationProblem& p, const FgoOptions& o) {
  const ImuSeries& imu = p.imu;
  const double t0 = p.initial.t_s;
  NodeLayout L;
  L.sample_count = imu.size();
  L.first_sample =
      static_cast<size_t>(std::upper_bound(imu.begin(), imu.end(), t0 + 1e-6,
                                           [](double t, const ImuSample& s) { return t < s.t_s; }) -
                          imu.begin());
  auto nearest = [&](double t) {
    auto it = std::lower_bound(imu.begin() + static_cast<long>(L.first_sample), imu.end(), t,
                               [](const ImuSample& s, double tt) { return s.t_s < tt; });
    size_t i = std::min(static_cast<size_t>(it - imu.begin()), imu.size() - 1);
    if (i > L.first_sample && std::abs(imu[i - 1].t_s - t) < std::abs(imu[i].t_s - t)) --i;
    return i;
  };
  std::vector<std::pair<size_t, size_t>> at;  // (anchor sample, fix number)
  for (const GnssFix& f : p.gnss) {
    bool withheld = false;
    for (const TimeWindow& w : p.outages) withheld = withheld || w.contains(f.t_s);
    if (withheld) {
      ++L.gnss_withheld;
      continue;
    }
    if (f.t_s <= t0 + 1e-6 || f.t_s > imu.back().t_s + 0.5 * imu.back().dt_s) continue;
    size_t i = nearest(f.t_s);
    if (std::abs(imu[i].t_s - f.t_s) > imu[i].dt_s) continue;
    if (!at.empty() && i < at.back().first + 2) {
      i = at.back().first;
    } else if (at.empty()) {
      i = std::max(i, L.first_sample + 1);
    }
    GnssObservation obs;
    obs.fix = f;
    obs.z_w.setZero();  // not compared
    obs.sqrt_info_w.setZero();
    obs.dt_s = f.t_s - imu[i].t_s;
    at.emplace_back(i, L.fixes.size());
    L.fixes.push_back(obs);
  }
  std::vector<size_t> anchors;
  for (const auto& a : at)
    if (anchors.empty() || anchors.back() != a.first) anchors.push_back(a.first);
  const size_t last_end = anchors.empty() ? L.first_sample : anchors.back() + 1;
  if (imu.size() >= last_end + 2) anchors.push_back(imu.size() - 1);
  L.nodes.push_back(GraphNode{t0, L.first_sample, {}});
  size_t g = 0;
  for (size_t a : anchors) {
    const double t_prev = L.nodes.back().t_s, t_a = imu[a].t_s;
    const int n_sub = static_cast<int>(std::ceil((t_a - t_prev) / o.max_node_spacing_s - 0.25));
    for (int m = 1; m < n_sub; ++m) {
      const size_t i = nearest(t_prev + (t_a - t_prev) * m / n_sub);
      if (i + 1 >= L.nodes.back().sample_end + 2 && i + 2 <= a)
        L.nodes.push_back(GraphNode{imu[i].t_s, i + 1, {}});
    }
    GraphNode n{t_a, a + 1, {}};
    for (; g < at.size() && at[g].first <= a; ++g) n.gnss.push_back(at[g].second);
    L.nodes.push_back(n);
  }
  return L;
}

EstimationProblem layoutProblem() {
  const test::Scenario sc = test::makeScenario(40.0, 200.0, 10.0);
  EstimationProblem p;
  p.imu = sc.ideal;
  p.imu.erase(p.imu.begin() + 3000, p.imu.begin() + 3100);  // a 0.5 s IMU gap at 15 s
  p.imu[3000].dt_s = p.imu[3000].t_s - p.imu[2999].t_s;
  p.initial = sc.truth.front();
  p.gnss = test::makeGnss(sc, Eigen::Vector3d::Zero(), 1.0, 0.02, 3);
  for (GnssFix& f : p.gnss) f.t_s += 0.0013;  // between sample ends
  GnssFix before = p.gnss.front(), late = p.gnss.back(), past = p.gnss.back();
  before.t_s = p.initial.t_s - 0.5;
  late.t_s = p.imu.back().t_s + 0.002;  // within half a sample of the last end: kept
  past.t_s = p.imu.back().t_s + 0.004;  // beyond: dropped
  p.gnss.push_back(before);
  p.gnss.push_back(late);
  p.gnss.push_back(past);
  std::stable_sort(p.gnss.begin(), p.gnss.end(),
                   [](const GnssFix& a, const GnssFix& b) { return a.t_s < b.t_s; });
  p.outages.push_back(TimeWindow{p.initial.t_s + 20.0, p.initial.t_s + 28.5});
  return p;
}

TEST(NodeLayout, StreamedPassEqualsTheDirectConstruction) {
  const EstimationProblem p = layoutProblem();
  const LocalFrame frame(p.initial.pos);
  FgoOptions o;
  o.max_node_spacing_s = 0.4;
  const NodeLayout want = directLayout(p, o);
  ASSERT_GT(want.nodes.size(), 60u);
  ASSERT_GT(want.gnss_withheld, 5);
  for (size_t block : {size_t{1}, size_t{7}, size_t{1000}, p.imu.size()}) {
    const NodeLayout got = buildNodeLayout(p, frame, o, [&](const ImuBlockFn& fn) {
      for (size_t i = 0; i < p.imu.size(); i += block) {
        fn(ImuSeries(p.imu.begin() + static_cast<long>(i),
                     p.imu.begin() + static_cast<long>(std::min(i + block, p.imu.size()))));
      }
    });
    EXPECT_EQ(got.sample_count, want.sample_count) << block;
    EXPECT_EQ(got.first_sample, want.first_sample) << block;
    EXPECT_EQ(got.gnss_withheld, want.gnss_withheld) << block;
    ASSERT_EQ(got.fixes.size(), want.fixes.size()) << block;
    for (size_t i = 0; i < want.fixes.size(); ++i) {
      EXPECT_EQ(got.fixes[i].fix.t_s, want.fixes[i].fix.t_s) << i;
      EXPECT_EQ(got.fixes[i].dt_s, want.fixes[i].dt_s) << i;
    }
    ASSERT_EQ(got.nodes.size(), want.nodes.size()) << block;
    for (size_t k = 0; k < want.nodes.size(); ++k) {
      EXPECT_EQ(got.nodes[k].t_s, want.nodes[k].t_s) << k;
      EXPECT_EQ(got.nodes[k].sample_end, want.nodes[k].sample_end) << k;
      EXPECT_EQ(got.nodes[k].gnss, want.nodes[k].gnss) << k;
    }
  }
}

TEST(NodeLayout, RefusesGnssOutOfTimeOrder) {
  EstimationProblem p = layoutProblem();
  std::swap(p.gnss[10], p.gnss[11]);
  const LocalFrame frame(p.initial.pos);
  EXPECT_THROW(buildNodeLayout(p, frame, FgoOptions{}, seriesPass(p.imu)), std::invalid_argument);
}

TEST(NodeLayout, StreamedGnssEqualsHeldGnss) {
  const EstimationProblem held = layoutProblem();
  EstimationProblem streamed = held;
  streamed.gnss.clear();
  streamed.gnss_stream = [&held]() { return seriesGnssSource(held.gnss); };
  const LocalFrame frame(held.initial.pos);
  FgoOptions o;
  o.max_node_spacing_s = 0.4;
  const NodeLayout want = buildNodeLayout(held, frame, o, seriesPass(held.imu));
  const NodeLayout got = buildNodeLayout(streamed, frame, o, seriesPass(held.imu));
  EXPECT_EQ(got.gnss_withheld, want.gnss_withheld);
  ASSERT_EQ(got.fixes.size(), want.fixes.size());
  for (size_t i = 0; i < want.fixes.size(); ++i) {
    EXPECT_EQ(got.fixes[i].fix.t_s, want.fixes[i].fix.t_s) << i;
    EXPECT_EQ(got.fixes[i].z_w, want.fixes[i].z_w) << i;
  }
  ASSERT_EQ(got.nodes.size(), want.nodes.size());
  for (size_t k = 0; k < want.nodes.size(); ++k) EXPECT_EQ(got.nodes[k].gnss, want.nodes[k].gnss);
}

}  // namespace
}  // namespace graftnav
