#include "graftnav/graph/sliding_window.h"

#include <ceres/solver.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <map>
#include <string>
#include <stdexcept>

namespace graftnav {
namespace {

struct NodeResiduals {
  ceres::ResidualBlockId prior = nullptr;
  ceres::ResidualBlockId preint_out = nullptr;
  ceres::ResidualBlockId bias_out = nullptr;
  PreintegrationFactor* preint_factor = nullptr;
  std::vector<std::pair<ceres::ResidualBlockId, size_t>> gnss;
};

ceres::Solver::Options windowSolverOptions(const FgoOptions& o) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  so.max_num_iterations = o.window_iterations;
  // LM damps each parameter by diag(J^T J) / radius. The preintegration factors between 10 Hz
  // nodes are stiff (information ~1e8 on position) while the window's GNSS-observed modes (a
  // common shift, velocity, biases) carry ~0.1: with Ceres' default radius 1e4 those modes are
  // damped by ~1e5 and a 4-iteration solve barely moves them, so the window dead-reckons and
  // diverges on a MEMS with a 0.5 m/s^2 accelerometer error. The problem is nearly linear over
  // a window (steps are accepted with relative decrease ~1): start almost undamped.
  so.initial_trust_region_radius = o.initial_trust_region_radius;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  return so;
}

}  // namespace

NodePriorFactor* marginalizeNode(FgoGraph& graph, ceres::Problem& problem, size_t m,
                                 const std::vector<ceres::ResidualBlockId>& residuals) {
  constexpr int kN = 30;
  // Tangent offset of every parameter block of nodes m and m+1.
  std::map<const double*, int> offset;
  for (int n = 0; n < 2; ++n) {
    NodeBlocks& b = graph.blocks(m + n);
    offset[b.p] = 15 * n + 0;
    offset[b.q] = 15 * n + 3;
    offset[b.v] = 15 * n + 6;
    offset[b.bg] = 15 * n + 9;
    offset[b.ba] = 15 * n + 12;
  }
  Eigen::Matrix<double, kN, kN> H = Eigen::Matrix<double, kN, kN>::Zero();
  Eigen::Matrix<double, kN, 1> g = Eigen::Matrix<double, kN, 1>::Zero();
  for (ceres::ResidualBlockId id : residuals) {
    const ceres::CostFunction* cost = problem.GetCostFunctionForResidualBlock(id);
    const ceres::LossFunction* loss = problem.GetLossFunctionForResidualBlock(id);
    std::vector<double*> blocks;
    problem.GetParameterBlocksForResidualBlock(id, &blocks);
    const int nr = cost->num_residuals();
    const std::vector<int32_t>& sizes = cost->parameter_block_sizes();
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
        blocks.size());
    std::vector<double*> jac_ptrs(blocks.size());
    for (size_t i = 0; i < blocks.size(); ++i) {
      J[i].resize(nr, sizes[i]);
      jac_ptrs[i] = J[i].data();
    }
    Eigen::VectorXd r(nr);
    if (!cost->Evaluate(blocks.data(), r.data(), jac_ptrs.data())) {
      throw std::runtime_error("marginalizeNode: a factor failed to evaluate at node " +
                               std::to_string(m));
    }
    double scale = 1.0;
    if (loss != nullptr) {
      double rho[3];
      loss->Evaluate(r.squaredNorm(), rho);
      scale = std::sqrt(std::max(rho[1], 0.0));
    }
    r *= scale;
    Eigen::MatrixXd Jt = Eigen::MatrixXd::Zero(nr, kN);
    for (size_t i = 0; i < blocks.size(); ++i) {
      auto it = offset.find(blocks[i]);
      if (it == offset.end()) {
        throw std::logic_error("marginalizeNode: factor touches a block outside nodes m, m+1");
      }
      if (sizes[i] == 4) {
        Eigen::Matrix<double, 4, 3, Eigen::RowMajor> P;
        graph.quaternionManifold()->PlusJacobian(blocks[i], P.data());
        Jt.block(0, it->second, nr, 3) = scale * J[i] * P;
      } else {
        Jt.block(0, it->second, nr, 3) = scale * J[i];
      }
    }
    H += Jt.transpose() * Jt;
    g += Jt.transpose() * r;
  }
  // Schur complement on the kept node (second half).
  const Eigen::Matrix<double, 15, 15> Hmm = 0.5 * (H.topLeftCorner<15, 15>() +
                                                   H.topLeftCorner<15, 15>().transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 15, 15>> es_m(Hmm);
  const double tol_m = 1e-12 * std::max(es_m.eigenvalues().maxCoeff(), 1e-300);
  Eigen::Matrix<double, 15, 1> inv_l;
  for (int i = 0; i < 15; ++i) {
    const double l = es_m.eigenvalues()(i);
    inv_l(i) = l > tol_m ? 1.0 / l : 0.0;
  }
  const Eigen::Matrix<double, 15, 15> Hmm_inv =
      es_m.eigenvectors() * inv_l.asDiagonal() * es_m.eigenvectors().transpose();
  const Eigen::Matrix<double, 15, 15> Hrm = H.bottomLeftCorner<15, 15>();
  Eigen::Matrix<double, 15, 15> Hp = H.bottomRightCorner<15, 15>() - Hrm * Hmm_inv * Hrm.transpose();
  Hp = 0.5 * (Hp + Hp.transpose()).eval();
  const Eigen::Matrix<double, 15, 1> gp = g.tail<15>() - Hrm * Hmm_inv * g.head<15>();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 15, 15>> es(Hp);
  const double tol = 1e-12 * std::max(es.eigenvalues().maxCoeff(), 1e-300);
  Eigen::Matrix<double, 15, 1> sq, isq;
  for (int i = 0; i < 15; ++i) {
    const double l = es.eigenvalues()(i);
    sq(i) = l > tol ? std::sqrt(l) : 0.0;
    isq(i) = l > tol ? 1.0 / std::sqrt(l) : 0.0;
  }
  // H' = S^T S with S = sqrt(L) V^T; e = sqrt(L)^-1 V^T g' so that S^T e = g'.
  const NodePriorFactor::Matrix15d S = sq.asDiagonal() * es.eigenvectors().transpose();
  const NodePriorFactor::Vector15d e = isq.asDiagonal() * (es.eigenvectors().transpose() * gp);
  return new NodePriorFactor(graph.blocks(m + 1).value(), S, e);
}

WindowResult runSlidingWindow(FgoGraph& graph, FgoReport* report) {
  const FgoOptions& opt = graph.options();
  const size_t n = graph.nodes().size();
  WindowResult out;
  out.causal.resize(n);
  out.lagged.resize(n);
  std::vector<NodeResiduals> res(n);

  ceres::Problem::Options po;
  po.enable_fast_removal = true;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  const ceres::Solver::Options so = windowSolverOptions(opt);
  int culled = 0, reint = 0, solves = 0, iterations = 0;
  size_t solving_node = 0;  // newest node, named in errors
  auto solve = [&]() {
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (summary.termination_type == ceres::FAILURE) {
      throw std::runtime_error("runSlidingWindow: Ceres failed at node " + std::to_string(solving_node) +
                               " (t=" + std::to_string(graph.nodes()[solving_node].t_s) +
                               "): " + summary.message);
    }
    ++solves;
    iterations += static_cast<int>(summary.iterations.size());
  };

  graph.addNodeBlocks(&problem, 0);
  res[0].prior = problem.AddResidualBlock(graph.makeInitialPrior(), nullptr, graph.nodeBlocks(0));
  out.causal[0] = graph.blocks(0).value();
  size_t oldest = 0;
  double last_gnss_t = graph.nodes()[0].t_s, reacquired_t = graph.nodes()[0].t_s;
  int consecutive_culls = 0;
  for (size_t k = 1; k < n; ++k) {
    const double t_k = graph.nodes()[k].t_s;
    solving_node = k;
    if (!graph.nodes()[k].gnss.empty()) {
      if (t_k - last_gnss_t > 2.0 * opt.max_node_spacing_s) reacquired_t = t_k;
      last_gnss_t = t_k;
    }
    graph.preintegrate(k - 1);
    graph.predictNode(k);
    graph.addNodeBlocks(&problem, k);
    PreintegrationFactor* pf = graph.makePreintegrationFactor(k - 1);
    res[k - 1].preint_factor = pf;
    res[k - 1].preint_out = problem.AddResidualBlock(pf, nullptr, graph.preintegrationBlocks(k - 1));
    res[k - 1].bias_out =
        problem.AddResidualBlock(graph.makeBiasFactor(k - 1), nullptr, graph.biasBlocks(k - 1));
    // Right after a GNSS gap the fixes must pull a drifted estimate back by metres: no robust
    // loss (it would weigh them down by the drift in sigmas) and no culling for cull_grace_s.
    const bool reacquiring = t_k - reacquired_t <= opt.cull_grace_s;
    for (size_t fix : graph.nodes()[k].gnss) {
      res[k].gnss.emplace_back(
          problem.AddResidualBlock(graph.makeGnssFactor(fix), reacquiring ? nullptr : graph.gnssLoss(),
                                   graph.poseBlocks(k)),
          fix);
    }
    const bool solve_now = (k % static_cast<size_t>(opt.window_solve_stride) == 0) || k + 1 == n;
    if (solve_now) solve();
    // Chi-square culling of the newest node's fixes, then re-solve.
    const bool may_cull = !reacquiring && consecutive_culls < opt.max_consecutive_culls;
    if (!res[k].gnss.empty() && !may_cull) consecutive_culls = 0;
    if (solve_now && opt.culling_rounds > 0 && may_cull && !res[k].gnss.empty()) {
      bool removed = false;
      for (auto it = res[k].gnss.begin(); it != res[k].gnss.end();) {
        if (graph.gnssChi2(it->second, k) > opt.chi2_threshold) {
          problem.RemoveResidualBlock(it->first);
          it = res[k].gnss.erase(it);
          ++culled;
          removed = true;
        } else {
          ++it;
        }
      }
      consecutive_culls = removed ? consecutive_culls + 1 : 0;
      if (removed) solve();
    }
    // Re-preintegrate window intervals whose bias moved far from their linearization point.
    for (size_t j = oldest; solve_now && j < k; ++j) {
      if (graph.biasMovedFar(j)) {
        graph.preintegrate(j);
        res[j].preint_factor->refresh();
        ++reint;
      }
    }
    out.causal[k] = graph.blocks(k).value();
    graph.requireFinite(k, k + 1, "runSlidingWindow");

    if (k - oldest + 1 > static_cast<size_t>(opt.window_nodes)) {
      std::vector<ceres::ResidualBlockId> ids;
      if (res[oldest].prior) ids.push_back(res[oldest].prior);
      ids.push_back(res[oldest].preint_out);
      ids.push_back(res[oldest].bias_out);
      for (const auto& gq : res[oldest].gnss) ids.push_back(gq.first);
      NodePriorFactor* prior = marginalizeNode(graph, problem, oldest, ids);
      out.lagged[oldest] = graph.blocks(oldest).value();
      for (double* b : graph.nodeBlocks(oldest)) problem.RemoveParameterBlock(b);
      ++oldest;
      res[oldest].prior = problem.AddResidualBlock(prior, nullptr, graph.nodeBlocks(oldest));
    }
  }
  for (size_t k = oldest; k < n; ++k) out.lagged[k] = graph.blocks(k).value();
  if (report) {
    report->gnss_culled += culled;
    report->reintegrations += reint;
    report->solves += solves;
    report->iterations += iterations;
  }
  return out;
}

}  // namespace graftnav
