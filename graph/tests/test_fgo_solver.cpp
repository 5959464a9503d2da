// Batch and sliding-window factor-graph solvers on a truth-by-construction case with IMU errors,
// GNSS noise, an outage and an outlier; marginalization against the full solution.
#include <ceres/covariance.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include "graftnav/nav/rotation.h"
#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/fgo_solver.h"
#include "graftnav/graph/sliding_window.h"
#include "graph_scenario.h"
#include "test_support.h"

namespace graftnav {
namespace {

struct Case {
  test::Scenario sc;
  EstimationProblem problem;
  test::ImuErrors err;
};

Case makeCase(double duration_s, double outage_start_s, double outage_len_s) {
  Case c;
  c.sc = test::makeScenario(duration_s, 200.0, 12.0);
  c.err.bg_rad_s << 4e-5, -3e-5, 5e-5;  // ~10 deg/h, MEMS
  c.err.ba_m_s2 << 8e-3, -6e-3, 5e-3;   // ~0.8 mg
  c.err.arw_rad_sqrt_s = 4.4e-5;        // 0.15 deg/sqrt(h)
  c.err.vrw_m_s_sqrt_s = 1e-3;          // 0.06 m/s/sqrt(h)
  EstimationProblem& p = c.problem;
  p.imu = test::addImuErrors(c.sc.ideal, c.err, 42);
  p.lever_arm_b_m << 0.3, -0.2, -1.1;
  p.gnss = test::makeGnss(c.sc, p.lever_arm_b_m, 1.0, 0.02, 43);
  const double t0 = c.sc.truth.front().t_s;
  p.outages.push_back({t0 + outage_start_s, t0 + outage_start_s + outage_len_s});
  p.initial = c.sc.truth.front();
  p.imu_profile.arw_rad_sqrt_s = c.err.arw_rad_sqrt_s;
  p.imu_profile.vrw_m_s_sqrt_s = c.err.vrw_m_s_sqrt_s;
  p.imu_profile.gyro_bias_instability_rad_s = 5e-5;
  p.imu_profile.accel_bias_instability_m_s2 = 1e-2;
  p.initial_sigma << 0.05, 0.05, 0.05, 0.02, 0.02, 0.02, 1e-3, 1e-3, 5e-3;
  return c;
}

double horizontalError(const NavState& est, const NavState& truth) {
  const Eigen::Vector3d d = earth::nedFromGeodetic(truth.pos, est.pos);
  return d.head<2>().norm();
}

// RMS horizontal error over the epochs inside the problem's outage.
double outageRms(const NavSolution& sol, const Case& c) {
  double s = 0.0;
  int n = 0;
  for (size_t k = 0; k < sol.states.size(); ++k) {
    if (!c.problem.outages[0].contains(sol.states[k].t_s)) continue;
    EXPECT_NEAR(sol.states[k].t_s, c.sc.truth[k].t_s, 1e-9);
    const double e = horizontalError(sol.states[k], c.sc.truth[k]);
    s += e * e;
    ++n;
  }
  return std::sqrt(s / n);
}

TEST(FgoSolver, BatchBeatsWindowInOutageAndRecoversAccelBias) {
  const Case c = makeCase(150.0, 90.0, 30.0);
  FgoOptions opt;
  FgoReport rb, rw;
  const NavSolution batch = solveBatchFgo(c.problem, opt, &rb);
  const NavSolution window = solveWindowFgo(c.problem, opt, &rw);
  ASSERT_EQ(batch.states.size(), c.problem.imu.size() + 1);
  ASSERT_EQ(window.states.size(), c.problem.imu.size() + 1);
  EXPECT_EQ(batch.gnss_withheld, 31);  // [90 s, 120 s], both ends inside
  // Culling only removes fixes whose injected noise is itself extreme (by construction).
  EXPECT_LE(batch.gnss_rejected, 2);
  for (double t : rb.culled_times_s) {
    const size_t k = static_cast<size_t>(std::llround((t - c.sc.truth.front().t_s) * 200.0));
    const Eigen::Vector3d ant = c.sc.truth[k].q_nb * c.problem.lever_arm_b_m;
    for (const GnssFix& f : c.problem.gnss) {
      if (std::abs(f.t_s - t) > 1e-6) continue;
      const Eigen::Vector3d noise =
          earth::nedFromGeodetic(earth::offsetByNed(c.sc.truth[k].pos, ant), f.pos) / 0.02;
      EXPECT_GT(noise.squaredNorm(), 0.6 * opt.chi2_threshold) << "culled a good fix at " << t;
    }
  }
  const double e_batch = outageRms(batch, c);
  const double e_window = outageRms(window, c);
  // Smoothing over both ends of the outage beats a causal estimate by far.
  EXPECT_LT(e_batch, 0.5 * e_window) << rb.summary << "\n" << rw.summary;
  EXPECT_LT(e_batch, 0.5);  // 30 s of a ~1 mg MEMS: free drift would be ~4 m
  // Outside the outage the solution sits at the GNSS noise level.
  const size_t k_mid = 60 * 200;
  EXPECT_LT(horizontalError(batch.states[k_mid], c.sc.truth[k_mid]), 0.05);
  // Horizontal accelerometer biases are observable through the manoeuvres.
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(batch.accel_bias_m_s2[k_mid](i), c.err.ba_m_s2(i), 2e-3) << "axis " << i;
  }
}

TEST(FgoSolver, MarginalCovarianceIsConsistent) {
  const Case c = makeCase(100.0, 50.0, 30.0);
  FgoOptions opt;
  opt.compute_covariance = true;
  const NavSolution sol = solveBatchFgo(c.problem, opt);
  ASSERT_EQ(sol.sigma.size(), sol.states.size());
  // Normalized position errors at node epochs (every second): about unit variance, and the
  // outage sigma grows above the GNSS-aided one.
  double sum_sq = 0.0;
  int n = 0;
  for (size_t k = 200; k < sol.states.size(); k += 200) {
    const Eigen::Vector3d e = earth::nedFromGeodetic(c.sc.truth[k].pos, sol.states[k].pos);
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(std::isfinite(sol.sigma[k](i)));
      sum_sq += std::pow(e(i) / sol.sigma[k](i), 2);
      ++n;
    }
  }
  const double mean = sum_sq / n;
  EXPECT_GT(mean, 0.3);
  EXPECT_LT(mean, 3.0);
  EXPECT_GT(sol.sigma[65 * 200](0), 3.0 * sol.sigma[20 * 200](0));  // mid-outage vs aided
}

TEST(FgoSolver, CullsGnssOutlier) {
  Case c = makeCase(60.0, 40.0, 10.0);
  // A 25 m jump at one epoch (multipath-like) far outside its 2 cm sigma.
  GnssFix& bad = c.problem.gnss[20];
  bad.pos = earth::offsetByNed(bad.pos, Eigen::Vector3d(25.0, -10.0, 5.0));
  FgoOptions opt;
  FgoReport rep;
  const NavSolution sol = solveBatchFgo(c.problem, opt, &rep);
  EXPECT_EQ(sol.gnss_rejected, 1) << rep.summary;
  const size_t k = static_cast<size_t>(std::llround((bad.t_s - c.sc.truth.front().t_s) * 200.0));
  EXPECT_LT(horizontalError(sol.states[k], c.sc.truth[k]), 0.05);
}

TEST(FgoSolver, EarthRotationSwitchChangesOutageDrift) {
  const Case c = makeCase(150.0, 90.0, 30.0);
  FgoOptions on, off;
  off.earth_rotation = false;
  const double e_on = outageRms(solveWindowFgo(c.problem, on), c);
  const double e_off = outageRms(solveWindowFgo(c.problem, off), c);
  EXPECT_GT(e_off, e_on);
}

// Marginalizing node 0 at the optimum of a 3-node graph leaves the optimum of nodes 1, 2 and
// node 1's marginal covariance unchanged (exact for the Gauss-Newton system at the optimum).
TEST(FgoSolver, MarginalizationPreservesOptimumAndCovariance) {
  Case c = makeCase(4.0, 100.0, 1.0);
  c.problem.imu.resize(2 * 200);  // 2 s: nodes at 0, 1, 2 s
  FgoOptions opt;
  FgoGraph graph(c.problem, opt);
  ASSERT_EQ(graph.nodeCount(), 3u);
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.enable_fast_removal = true;
  ceres::Problem full(po);
  graph.addNodeBlocks(&full, 0);
  ceres::ResidualBlockId prior =
      full.AddResidualBlock(graph.makeInitialPrior(), nullptr, graph.nodeBlocks(0));
  std::vector<ceres::ResidualBlockId> touching0 = {prior};
  for (size_t k = 1; k < 3; ++k) {
    graph.preintegrate(k - 1);
    graph.predictNode(k);
    graph.addNodeBlocks(&full, k);
    auto id1 = full.AddResidualBlock(graph.makePreintegrationFactor(k - 1), nullptr,
                                     graph.preintegrationBlocks(k - 1));
    auto id2 = full.AddResidualBlock(graph.makeBiasFactor(k - 1), nullptr, graph.biasBlocks(k - 1));
    if (k == 1) touching0.insert(touching0.end(), {id1, id2});
    for (size_t fix : graph.node(k).gnss)
      full.AddResidualBlock(graph.makeGnssFactor(fix), nullptr, graph.poseBlocks(k));
  }
  ceres::Solver::Options so;
  so.max_num_iterations = 50;
  so.function_tolerance = 1e-14;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &full, &summary);
  const NodeValue x1 = graph.blocks(1).value(), x2 = graph.blocks(2).value();
  ceres::Covariance::Options co;
  ceres::Covariance cov_full(co);
  const double* pv1 = graph.blocks(1).v;
  const std::vector<std::pair<const double*, const double*>> pairs = {{pv1, pv1}};
  ASSERT_TRUE(cov_full.Compute(pairs, &full));
  Eigen::Matrix3d Pv_full;
  cov_full.GetCovarianceBlock(pv1, pv1, Pv_full.data());

  ceres::CostFunction* mprior = marginalizeNode(graph, full, 0, touching0);
  for (double* b : graph.nodeBlocks(0)) full.RemoveParameterBlock(b);
  full.AddResidualBlock(mprior, nullptr, graph.nodeBlocks(1));
  // Perturb, re-solve: must return to the same optimum.
  graph.blocks(2).p[0] += 0.5;
  graph.blocks(1).v[1] -= 0.1;
  ceres::Solve(so, &full, &summary);
  EXPECT_LT((graph.blocks(1).value().p_w - x1.p_w).norm(), 1e-6);
  EXPECT_LT((graph.blocks(1).value().v_w - x1.v_w).norm(), 1e-6);
  EXPECT_LT((graph.blocks(2).value().p_w - x2.p_w).norm(), 1e-6);
  ceres::Covariance cov_marg(co);
  ASSERT_TRUE(cov_marg.Compute(pairs, &full));
  Eigen::Matrix3d Pv_marg;
  cov_marg.GetCovarianceBlock(pv1, pv1, Pv_marg.data());
  EXPECT_LT((Pv_marg - Pv_full).norm(), 1e-3 * Pv_full.norm()) << Pv_full << "\n\n" << Pv_marg;
}

}  // namespace
}  // namespace graftnav
