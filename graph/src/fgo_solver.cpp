#include "graftnav/graph/fgo_solver.h"

#include <ceres/covariance.h>
#include <ceres/solver.h>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/sliding_window.h"

namespace graftnav {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Marginal covariance of p, v and attitude of every node, as NED 1-sigmas at the node.
std::vector<PvaSigma> nodeSigmas(FgoGraph& graph, ceres::Problem& problem, int num_threads) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::SPARSE_QR;
  co.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  co.num_threads = num_threads;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> pairs;
  const size_t n = graph.nodes().size();
  for (size_t k = 0; k < n; ++k) {
    const NodeBlocks& b = graph.blocks(k);
    pairs.emplace_back(b.p, b.p);
    pairs.emplace_back(b.v, b.v);
    pairs.emplace_back(b.q, b.q);
  }
  std::vector<PvaSigma> out(n, PvaSigma::Constant(std::nan("")));
  if (!cov.Compute(pairs, &problem)) return out;
  for (size_t k = 0; k < n; ++k) {
    const NodeBlocks& b = graph.blocks(k);
    const NodeValue x = b.value();
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Pp, Pv, Pq;
    cov.GetCovarianceBlock(b.p, b.p, Pp.data());
    cov.GetCovarianceBlock(b.v, b.v, Pv.data());
    cov.GetCovarianceBlockInTangentSpace(b.q, b.q, Pq.data());
    const Eigen::Matrix3d C_nw = graph.frame().C_nw(graph.frame().toGeodetic(x.p_w));
    const Eigen::Matrix3d C_nb = C_nw * x.q_wb.toRotationMatrix();
    PvaSigma s;
    s.segment<3>(0) = (C_nw * Pp * C_nw.transpose()).diagonal().cwiseSqrt();
    s.segment<3>(3) = (C_nw * Pv * C_nw.transpose()).diagonal().cwiseSqrt();
    s.segment<3>(6) = (C_nb * Pq * C_nb.transpose()).diagonal().cwiseSqrt();
    out[k] = s;
  }
  return out;
}

// The output into the solution, or to `output` when given (the solution then has no states).
NavSolution integrate(const FgoGraph& graph, const std::string& estimator,
                      const std::vector<PvaSigma>& sigma, const FgoEpochFn& output) {
  if (!output) return graph.integrateOutput(estimator, sigma);
  graph.integrateOutput(sigma, output);
  NavSolution sol;
  sol.estimator = estimator;
  sol.gnss_withheld = graph.gnssWithheld();
  return sol;
}

}  // namespace

NavSolution solveWindowFgo(const EstimationProblem& problem, const FgoOptions& options,
                           FgoReport* report, const FgoEpochFn& output) {
  FgoReport local;
  FgoReport& rep = report ? *report : local;
  auto t0 = std::chrono::steady_clock::now();
  FgoGraph graph(problem, options);
  WindowResult wr = runSlidingWindow(graph, &rep);
  rep.window_time_s = secondsSince(t0);
  const std::vector<NodeValue>& values = options.window_fixed_lag_output ? wr.lagged : wr.causal;
  for (size_t k = 0; k < values.size(); ++k) graph.blocks(k).set(values[k]);
  graph.requireFinite(0, values.size(), "solveWindowFgo");
  rep.nodes = static_cast<int>(graph.nodes().size());
  rep.gnss_factors = static_cast<int>(graph.fixes().size());
  t0 = std::chrono::steady_clock::now();
  NavSolution sol = integrate(graph, "fgo-window", {}, output);
  rep.output_time_s = secondsSince(t0);
  sol.gnss_used = rep.gnss_factors - rep.gnss_culled;
  sol.gnss_rejected = rep.gnss_culled;
  rep.summary = fmt::format("fgo-window: {} nodes, {} GNSS ({} culled), {} re-preintegrations, "
                            "{} solves, {:.3f} s",
                            rep.nodes, rep.gnss_factors, rep.gnss_culled, rep.reintegrations,
                            rep.solves, rep.window_time_s);
  return sol;
}

NavSolution solveBatchFgo(const EstimationProblem& problem, const FgoOptions& options,
                          FgoReport* report, const FgoEpochFn& output) {
  FgoReport local;
  FgoReport& rep = report ? *report : local;
  auto t0 = std::chrono::steady_clock::now();
  FgoGraph graph(problem, options);
  // Initial values: a fixed-lag sliding-window pass that solves every batch_init_stride nodes
  // (counts of its culling are not kept: the batch re-decides every fix).
  {
    FgoOptions init = options;
    init.window_solve_stride = options.batch_init_stride;
    init.window_nodes = std::max(options.window_nodes, 2 * options.batch_init_stride);
    graph.setOptions(init);
    FgoReport wrep;
    runSlidingWindow(graph, &wrep);
    rep.reintegrations += wrep.reintegrations;
    graph.setOptions(options);
    graph.requireFinite(0, graph.nodes().size(), "solveBatchFgo (window initialization)");
  }
  rep.window_time_s = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();

  const size_t n = graph.nodes().size();
  rep.nodes = static_cast<int>(n);
  rep.gnss_factors = static_cast<int>(graph.fixes().size());
  ceres::Problem::Options po;
  po.enable_fast_removal = true;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem prob(po);
  std::vector<PreintegrationFactor*> pfs(n > 0 ? n - 1 : 0);
  std::vector<std::vector<std::pair<ceres::ResidualBlockId, size_t>>> gnss(n);
  for (size_t k = 0; k < n; ++k) graph.addNodeBlocks(&prob, k);
  prob.AddResidualBlock(graph.makeInitialPrior(), nullptr, graph.nodeBlocks(0));
  for (size_t k = 0; k + 1 < n; ++k) {
    if (graph.biasMovedFar(k)) {
      graph.preintegrate(k);
      ++rep.reintegrations;
    }
    pfs[k] = graph.makePreintegrationFactor(k);
    prob.AddResidualBlock(pfs[k], nullptr, graph.preintegrationBlocks(k));
    prob.AddResidualBlock(graph.makeBiasFactor(k), nullptr, graph.biasBlocks(k));
  }
  for (size_t k = 0; k < n; ++k) {
    for (size_t fix : graph.nodes()[k].gnss) {
      gnss[k].emplace_back(
          prob.AddResidualBlock(graph.makeGnssFactor(fix), graph.gnssLoss(), graph.poseBlocks(k)),
          fix);
    }
  }

  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  so.max_num_iterations = options.max_iterations;
  so.initial_trust_region_radius = options.initial_trust_region_radius;  // see sliding_window.cpp
  so.num_threads = options.num_threads;
  so.logging_type = ceres::SILENT;
  bool first = true;
  auto solve = [&]() {
    ceres::Solver::Summary summary;
    ceres::Solve(so, &prob, &summary);
    if (summary.termination_type == ceres::FAILURE) {
      throw std::runtime_error("solveBatchFgo: Ceres failed: " + summary.message);
    }
    graph.requireFinite(0, n, "solveBatchFgo (solve " + std::to_string(rep.solves + 1) + ")");
    if (first) rep.initial_cost = summary.initial_cost;
    first = false;
    rep.final_cost = summary.final_cost;
    ++rep.solves;
    rep.iterations += static_cast<int>(summary.iterations.size());
  };
  solve();
  for (int round = 0; round < options.culling_rounds; ++round) {
    // Candidates first: when more than max_cull_fraction of the fixes fail, the graph (not the
    // fixes) is wrong, and culling would only hide it.
    std::vector<std::pair<size_t, size_t>> bad;  // (node, position in gnss[node])
    std::vector<double> bad_chi2;
    for (size_t k = 0; k < n; ++k) {
      for (size_t i = 0; i < gnss[k].size(); ++i) {
        const double chi2 = graph.gnssChi2(gnss[k][i].second, k);
        if (chi2 > options.chi2_threshold) {
          bad.emplace_back(k, i);
          bad_chi2.push_back(chi2);
        }
      }
    }
    if (bad.empty()) break;
    if (bad.size() > options.max_cull_fraction * static_cast<double>(graph.fixes().size())) {
      rep.cull_refused = static_cast<int>(bad.size());
      break;
    }
    for (size_t b = bad.size(); b-- > 0;) {  // back to front keeps positions valid
      auto& list = gnss[bad[b].first];
      rep.culled_times_s.push_back(graph.fixes()[list[bad[b].second].second].fix.t_s);
      rep.culled_chi2.push_back(bad_chi2[b]);
      prob.RemoveResidualBlock(list[bad[b].second].first);
      list.erase(list.begin() + static_cast<long>(bad[b].second));
    }
    rep.gnss_culled += static_cast<int>(bad.size());
    solve();
  }
  for (int round = 0; round < options.max_reintegration_rounds; ++round) {
    int redone = 0;
    for (size_t k = 0; k + 1 < n; ++k) {
      if (graph.biasMovedFar(k)) {
        graph.preintegrate(k);
        pfs[k]->refresh();
        ++redone;
      }
    }
    rep.reintegrations += redone;
    if (redone == 0) break;
    solve();
  }
  rep.batch_time_s = secondsSince(t0);

  std::vector<PvaSigma> sig;
  if (options.compute_covariance) {
    t0 = std::chrono::steady_clock::now();
    sig = nodeSigmas(graph, prob, options.num_threads);
    rep.covariance_time_s = secondsSince(t0);
  }
  t0 = std::chrono::steady_clock::now();
  NavSolution sol = integrate(graph, "fgo", sig, output);
  rep.output_time_s = secondsSince(t0);
  sol.gnss_used = rep.gnss_factors - rep.gnss_culled;
  sol.gnss_rejected = rep.gnss_culled;
  rep.summary = fmt::format(
      "fgo: {} nodes, {} GNSS ({} culled), {} re-preintegrations, {} solves / {} iterations, "
      "cost {:.4g} -> {:.4g}, window init {:.3f} s, batch {:.3f} s{}",
      rep.nodes, rep.gnss_factors, rep.gnss_culled, rep.reintegrations, rep.solves,
      rep.iterations, rep.initial_cost, rep.final_cost, rep.window_time_s, rep.batch_time_s,
      rep.cull_refused > 0 ? fmt::format(" (culling refused: {} fixes failed)", rep.cull_refused)
                           : std::string());
  return sol;
}

}  // namespace graftnav
