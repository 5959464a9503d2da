#include "graftnav/graph/sliding_window.h"

#include <ceres/solver.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <deque>
#include <map>
#include <optional>
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
  // Vehicle aiding: the node's odometer / NHC factor, the scale walk to the next node, and (node
  // 0) the scale's prior; null when absent.
  ceres::ResidualBlockId vehicle = nullptr, scale_out = nullptr, scale_prior = nullptr;
  // IMU scale factors: their Gauss-Markov factor to the next node and (node 0) their prior.
  ceres::ResidualBlockId imu_scale_out = nullptr, imu_scale_prior = nullptr;
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

namespace {

// Tangent dimensions of one node: 15 (p, q, v, bg, ba), 16 with the odometer scale s, 21 with
// the IMU scale factors sg, sa, 22 with both (s last).
template <int N>
using PairMatrix = Eigen::Matrix<double, 2 * N, 2 * N>;
template <int N>
using PairVector = Eigen::Matrix<double, 2 * N, 1>;

// Adds J^T J and J^T r of one residual block (robust loss applied as a scale, quaternion
// Jacobians taken to the tangent) to H, g over the tangent of nodes m and m+1.
template <int N>
void accumulateBlock(FgoGraph& graph, ceres::Problem& problem, size_t m,
                     const std::map<const double*, int>& offset, ceres::ResidualBlockId id,
                     PairMatrix<N>* H, PairVector<N>* g) {
  constexpr int kN = 2 * N;
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
      Jt.block(0, it->second, nr, sizes[i]) = scale * J[i];
    }
  }
  *H += Jt.transpose() * Jt;
  *g += Jt.transpose() * r;
}

// Schur complement of H, g on the second node, factored as S^T S = H', S^T e = g'.
template <int N>
void schurOnSecondNode(const PairMatrix<N>& H, const PairVector<N>& g,
                       Eigen::Matrix<double, N, N>* S, Eigen::Matrix<double, N, 1>* e) {
  const Eigen::Matrix<double, N, N> Hmm =
      0.5 * (H.template topLeftCorner<N, N>() + H.template topLeftCorner<N, N>().transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es_m(Hmm);
  const double tol_m = 1e-12 * std::max(es_m.eigenvalues().maxCoeff(), 1e-300);
  Eigen::Matrix<double, N, 1> inv_l;
  for (int i = 0; i < N; ++i) {
    const double l = es_m.eigenvalues()(i);
    inv_l(i) = l > tol_m ? 1.0 / l : 0.0;
  }
  const Eigen::Matrix<double, N, N> Hmm_inv =
      es_m.eigenvectors() * inv_l.asDiagonal() * es_m.eigenvectors().transpose();
  const Eigen::Matrix<double, N, N> Hrm = H.template bottomLeftCorner<N, N>();
  Eigen::Matrix<double, N, N> Hp =
      H.template bottomRightCorner<N, N>() - Hrm * Hmm_inv * Hrm.transpose();
  Hp = 0.5 * (Hp + Hp.transpose()).eval();
  const Eigen::Matrix<double, N, 1> gp =
      g.template tail<N>() - Hrm * Hmm_inv * g.template head<N>();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(Hp);
  const double tol = 1e-12 * std::max(es.eigenvalues().maxCoeff(), 1e-300);
  Eigen::Matrix<double, N, 1> sq, isq;
  for (int i = 0; i < N; ++i) {
    const double l = es.eigenvalues()(i);
    sq(i) = l > tol ? std::sqrt(l) : 0.0;
    isq(i) = l > tol ? 1.0 / std::sqrt(l) : 0.0;
  }
  // H' = S^T S with S = sqrt(L) V^T; e = sqrt(L)^-1 V^T g' so that S^T e = g'.
  *S = sq.asDiagonal() * es.eigenvectors().transpose();
  *e = isq.asDiagonal() * (es.eigenvectors().transpose() * gp);
}

}  // namespace

namespace {

// H, g of the residual blocks over the tangent of nodes m and m+1 (N dims each), and their
// Schur complement on node m+1.
template <int N>
void marginalSystem(FgoGraph& graph, ceres::Problem& problem, size_t m,
                    const std::vector<ceres::ResidualBlockId>& residuals,
                    Eigen::Matrix<double, N, N>* S, Eigen::Matrix<double, N, 1>* e) {
  // Tangent offset of every parameter block of nodes m and m+1.
  std::map<const double*, int> offset;
  for (int n = 0; n < 2; ++n) {
    NodeBlocks& b = graph.blocks(m + n);
    offset[b.p] = N * n + 0;
    offset[b.q] = N * n + 3;
    offset[b.v] = N * n + 6;
    offset[b.bg] = N * n + 9;
    offset[b.ba] = N * n + 12;
    if (N >= 21) {
      offset[b.sg] = N * n + 15;
      offset[b.sa] = N * n + 18;
    }
    if (N == 16 || N == 22) offset[b.s] = N * n + N - 1;
  }
  PairMatrix<N> H = PairMatrix<N>::Zero();
  PairVector<N> g = PairVector<N>::Zero();
  for (ceres::ResidualBlockId id : residuals)
    accumulateBlock<N>(graph, problem, m, offset, id, &H, &g);
  schurOnSecondNode<N>(H, g, S, e);
}

// The marginalization prior on node m+1 when the nodes carry IMU scale factors.
template <int N>
ceres::CostFunction* marginalizeImuScaleNode(FgoGraph& graph, ceres::Problem& problem, size_t m,
                                             const std::vector<ceres::ResidualBlockId>& residuals) {
  Eigen::Matrix<double, N, N> S;
  Eigen::Matrix<double, N, 1> e;
  marginalSystem<N>(graph, problem, m, residuals, &S, &e);
  return new NodeImuScalePriorFactor(graph.blocks(m + 1).value(), S, e, N == 22);
}

}  // namespace

ceres::CostFunction* marginalizeNode(FgoGraph& graph, ceres::Problem& problem, size_t m,
                                     const std::vector<ceres::ResidualBlockId>& residuals) {
  if (graph.estimatesImuScale()) {
    return graph.estimatesOdometerScale()
               ? marginalizeImuScaleNode<22>(graph, problem, m, residuals)
               : marginalizeImuScaleNode<21>(graph, problem, m, residuals);
  }
  if (graph.estimatesOdometerScale()) {
    NodeScalePriorFactor::Matrix16d S;
    NodeScalePriorFactor::Vector16d e;
    marginalSystem<16>(graph, problem, m, residuals, &S, &e);
    return new NodeScalePriorFactor(graph.blocks(m + 1).value(), S, e);
  }
  NodePriorFactor::Matrix15d S;
  NodePriorFactor::Vector15d e;
  marginalSystem<15>(graph, problem, m, residuals, &S, &e);
  return new NodePriorFactor(graph.blocks(m + 1).value(), S, e);
}

namespace {

// The window over the graph's nodes: one node added at a time, the oldest marginalized.
class SlidingWindow {
 public:
  SlidingWindow(FgoGraph& graph, bool keep_preintegrations, WindowListener* listener);
  // Adds node k (k = 1, 2, ... in order); `samples` holds the window's intervals up to node k.
  void addNode(size_t k, const ImuSampleBuffer& samples);
  // Hands out the nodes still in the window (oldest first).
  void finish(const ImuSampleBuffer& samples);
  // First sample a later re-preintegration or listener call may need.
  size_t firstNeededSample() const {
    const size_t b = graph_.intervalBegin(oldest_);
    return b > 0 ? b - 1 : 0;
  }
  void addCounts(FgoReport* report) const;

 private:
  NodeResiduals& residuals(size_t k) { return res_[k - oldest_]; }
  // Every node placed and k the last of them.
  bool isLastNode(size_t k) const { return !graph_.placing() && k + 1 == graph_.nodeCount(); }
  void solve();
  void addFactors(size_t k);
  void cullNewest(size_t k, bool reacquiring, bool solved);
  void marginalizeOldest(const ImuSampleBuffer& samples);

  FgoGraph& graph_;
  const FgoOptions opt_;
  const bool keep_preintegrations_;
  WindowListener* listener_;
  WindowListener none_;
  ceres::Problem problem_;
  const ceres::Solver::Options so_;
  std::deque<NodeResiduals> res_;  // nodes [oldest_, newest]
  size_t oldest_ = 0, solving_node_ = 0;
  double last_gnss_t_ = 0.0, reacquired_t_ = 0.0;
  int consecutive_culls_ = 0;
  int culled_ = 0, reint_ = 0, solves_ = 0, iterations_ = 0, vehicle_ = 0;
};

ceres::Problem::Options windowProblemOptions() {
  ceres::Problem::Options po;
  po.enable_fast_removal = true;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return po;
}

SlidingWindow::SlidingWindow(FgoGraph& graph, bool keep_preintegrations, WindowListener* listener)
    : graph_(graph),
      opt_(graph.options()),
      keep_preintegrations_(keep_preintegrations),
      listener_(listener ? listener : &none_),
      problem_(windowProblemOptions()),
      so_(windowSolverOptions(graph.options())) {
  graph_.addNodeBlocks(&problem_, 0);
  res_.emplace_back();
  res_.front().prior =
      problem_.AddResidualBlock(graph_.makeInitialPrior(), nullptr, graph_.nodeBlocks(0));
  if (graph_.estimatesOdometerScale()) {
    res_.front().scale_prior =
        problem_.AddResidualBlock(graph_.makeScalePrior(), nullptr, {graph_.blocks(0).s});
  }
  if (graph_.estimatesImuScale()) {
    res_.front().imu_scale_prior = problem_.AddResidualBlock(
        graph_.makeImuScalePrior(), nullptr, {graph_.blocks(0).sg, graph_.blocks(0).sa});
  }
  last_gnss_t_ = reacquired_t_ = graph_.node(0).t_s;
  listener_->entered(0, graph_.blocks(0).value(), ImuSampleBuffer());
}

void SlidingWindow::solve() {
  ceres::Solver::Summary summary;
  ceres::Solve(so_, &problem_, &summary);
  if (summary.termination_type == ceres::FAILURE) {
    throw std::runtime_error(
        "runSlidingWindow: Ceres failed at node " + std::to_string(solving_node_) +
        " (t=" + std::to_string(graph_.node(solving_node_).t_s) + "): " + summary.message);
  }
  ++solves_;
  iterations_ += static_cast<int>(summary.iterations.size());
}

// Node k's blocks, the preintegration and bias factors from node k-1, and node k's fixes. Right
// after a GNSS gap the fixes must pull a drifted estimate back by metres: no robust loss (it
// would weigh them down by the drift in sigmas).
void SlidingWindow::addFactors(size_t k) {
  graph_.addNodeBlocks(&problem_, k);
  PreintegrationFactor* pf = graph_.makePreintegrationFactor(k - 1);
  NodeResiduals& prev = residuals(k - 1);
  prev.preint_factor = pf;
  prev.preint_out = problem_.AddResidualBlock(pf, nullptr, graph_.preintegrationBlocks(k - 1));
  prev.bias_out =
      problem_.AddResidualBlock(graph_.makeBiasFactor(k - 1), nullptr, graph_.biasBlocks(k - 1));
  if (graph_.estimatesOdometerScale()) {
    prev.scale_out = problem_.AddResidualBlock(graph_.makeScaleWalkFactor(k - 1), nullptr,
                                               graph_.scaleWalkBlocks(k - 1));
  }
  if (graph_.estimatesImuScale()) {
    prev.imu_scale_out = problem_.AddResidualBlock(graph_.makeImuScaleFactor(k - 1), nullptr,
                                                   graph_.imuScaleBlocks(k - 1));
  }
  res_.emplace_back();
  if (VehicleVelocityFactor* vf = graph_.makeVehicleFactor(k)) {
    res_.back().vehicle = problem_.AddResidualBlock(vf, nullptr, graph_.vehicleBlocks(k, *vf));
    ++vehicle_;
  }
  const bool reacquiring = graph_.node(k).t_s - reacquired_t_ <= opt_.cull_grace_s;
  for (size_t fix : graph_.node(k).gnss) {
    res_.back().gnss.emplace_back(
        problem_.AddResidualBlock(graph_.makeGnssFactor(fix),
                                  reacquiring ? nullptr : graph_.gnssLoss(), graph_.poseBlocks(k)),
        fix);
  }
}

// Chi-square culling of the newest node's fixes after a solve, then a re-solve (none for
// cull_grace_s after a GNSS gap, and not more than max_consecutive_culls in a row).
void SlidingWindow::cullNewest(size_t k, bool reacquiring, bool solved) {
  auto& gnss = residuals(k).gnss;
  const bool may_cull = !reacquiring && consecutive_culls_ < opt_.max_consecutive_culls;
  if (!gnss.empty() && !may_cull) consecutive_culls_ = 0;
  if (!solved || opt_.culling_rounds <= 0 || !may_cull || gnss.empty()) return;
  bool removed = false;
  for (auto it = gnss.begin(); it != gnss.end();) {
    if (graph_.gnssChi2(it->second, k) > opt_.chi2_threshold) {
      problem_.RemoveResidualBlock(it->first);
      it = gnss.erase(it);
      ++culled_;
      removed = true;
    } else {
      ++it;
    }
  }
  consecutive_culls_ = removed ? consecutive_culls_ + 1 : 0;
  if (removed) solve();
}

void SlidingWindow::addNode(size_t k, const ImuSampleBuffer& samples) {
  const double t_k = graph_.node(k).t_s;
  solving_node_ = k;
  if (!graph_.node(k).gnss.empty()) {
    if (t_k - last_gnss_t_ > 2.0 * opt_.max_node_spacing_s) reacquired_t_ = t_k;
    last_gnss_t_ = t_k;
  }
  graph_.preintegrate(k - 1, samples);
  graph_.predictNode(k);
  graph_.observeVehicle(k, samples);
  addFactors(k);
  const bool solve_now = (k % static_cast<size_t>(opt_.window_solve_stride) == 0) || isLastNode(k);
  if (solve_now) solve();
  cullNewest(k, t_k - reacquired_t_ <= opt_.cull_grace_s, solve_now);
  if (solve_now) {
    // Re-preintegrate window intervals whose bias moved far from their linearization point.
    for (size_t j = oldest_; j < k; ++j) {
      if (graph_.biasMovedFar(j)) {
        graph_.preintegrate(j, samples);
        residuals(j).preint_factor->refresh();
        ++reint_;
      }
    }
  }
  graph_.requireFinite(k, k + 1, "runSlidingWindow");
  listener_->entered(k, graph_.blocks(k).value(), samples);
  if (k - oldest_ + 1 > static_cast<size_t>(opt_.window_nodes)) marginalizeOldest(samples);
}

void SlidingWindow::marginalizeOldest(const ImuSampleBuffer& samples) {
  const NodeResiduals& r = res_.front();
  std::vector<ceres::ResidualBlockId> ids;
  if (r.prior) ids.push_back(r.prior);
  ids.push_back(r.preint_out);
  ids.push_back(r.bias_out);
  for (const auto& gq : r.gnss) ids.push_back(gq.first);
  for (ceres::ResidualBlockId id :
       {r.vehicle, r.scale_out, r.scale_prior, r.imu_scale_out, r.imu_scale_prior})
    if (id) ids.push_back(id);
  ceres::CostFunction* prior = marginalizeNode(graph_, problem_, oldest_, ids);
  listener_->left(oldest_, graph_.blocks(oldest_).value(), samples);
  // The factors first, in this fixed order: RemoveParameterBlock would remove them in the order
  // of a hash set of their addresses, which moves with the heap layout, and that order is the
  // order of the Jacobian's rows in later solves (their rounding).
  for (ceres::ResidualBlockId id : ids) problem_.RemoveResidualBlock(id);
  for (double* b : graph_.allBlocks(oldest_)) problem_.RemoveParameterBlock(b);
  if (!keep_preintegrations_) graph_.releasePreintegration(oldest_);
  res_.pop_front();
  ++oldest_;
  if (!keep_preintegrations_) graph_.forgetBefore(oldest_);
  res_.front().prior = problem_.AddResidualBlock(prior, nullptr, graph_.allBlocks(oldest_));
}

void SlidingWindow::finish(const ImuSampleBuffer& samples) {
  for (size_t k = oldest_; k < graph_.nodeCount(); ++k) {
    listener_->left(k, graph_.blocks(k).value(), samples);
  }
  listener_->finished(samples);
}

void SlidingWindow::addCounts(FgoReport* report) const {
  report->gnss_culled += culled_;
  report->reintegrations += reint_;
  report->solves += solves_;
  report->iterations += iterations_;
  report->vehicle_factors += vehicle_;
}

}  // namespace

void runSlidingWindow(FgoGraph& graph, const ImuPassFn& imu, FgoReport* report,
                      bool keep_preintegrations, WindowListener* listener) {
  std::optional<SlidingWindow> window;  // from the moment node 0 is placed
  ImuSampleBuffer samples;
  size_t next = 1;  // the next node to add
  const bool placing = graph.placing();
  auto addReady = [&]() {  // the nodes whose interval the buffer holds
    if (!window && graph.nodeCount() > 0) window.emplace(graph, keep_preintegrations, listener);
    while (window && next < graph.nodeCount() && graph.intervalEnd(next - 1) <= samples.end()) {
      window->addNode(next++, samples);
    }
  };
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      samples.push(s);
      if (placing) graph.placeSample(s);
      addReady();
      // Before node 0, only the sample before the next one may be needed (coning memory).
      samples.dropBefore(window ? window->firstNeededSample() : samples.end() - 1);
    }
  });
  if (placing) {
    graph.finishPlacing();
    addReady();
  }
  if (!window || next < graph.nodeCount()) {
    throw std::runtime_error("runSlidingWindow: the IMU pass ended before node " +
                             std::to_string(next) + " (fewer samples than the layout's)");
  }
  window->finish(samples);
  if (report) window->addCounts(report);
}

}  // namespace graftnav
