#include "graftnav/graph/fgo_solver.h"

#include <ceres/covariance.h>
#include <ceres/solver.h>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <stdexcept>

#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/sliding_window.h"

namespace graftnav {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Marginal covariance of p, v and attitude of every node, as NED 1-sigmas at the node.
std::vector<PvaSigma> nodeSigmas(FgoGraph& graph, ceres::Problem& problem, int num_threads,
                                 std::vector<double>* scale_sigma, FgoReport* rep) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::SPARSE_QR;
  co.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  co.num_threads = num_threads;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> pairs;
  const size_t n = graph.nodeCount();
  for (size_t k = 0; k < n; ++k) {
    const NodeBlocks& b = graph.blocks(k);
    pairs.emplace_back(b.p, b.p);
    pairs.emplace_back(b.v, b.v);
    pairs.emplace_back(b.q, b.q);
    if (graph.estimatesOdometerScale()) pairs.emplace_back(b.s, b.s);
  }
  const bool imu_scale = graph.estimatesImuScale() && n > 0;
  if (imu_scale) {
    pairs.emplace_back(graph.blocks(n - 1).sg, graph.blocks(n - 1).sg);
    pairs.emplace_back(graph.blocks(n - 1).sa, graph.blocks(n - 1).sa);
  }
  std::vector<PvaSigma> out(n, PvaSigma::Constant(std::nan("")));
  if (!cov.Compute(pairs, &problem)) return out;
  if (imu_scale) {
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Pg, Pa;
    cov.GetCovarianceBlock(graph.blocks(n - 1).sg, graph.blocks(n - 1).sg, Pg.data());
    cov.GetCovarianceBlock(graph.blocks(n - 1).sa, graph.blocks(n - 1).sa, Pa.data());
    rep->imu_scale_std_last << Pg.diagonal().cwiseMax(0.0).cwiseSqrt(),
        Pa.diagonal().cwiseMax(0.0).cwiseSqrt();
  }
  if (graph.estimatesOdometerScale()) {
    scale_sigma->assign(n, std::nan(""));
    for (size_t k = 0; k < n; ++k) {
      double var = 0.0;
      cov.GetCovarianceBlock(graph.blocks(k).s, graph.blocks(k).s, &var);
      (*scale_sigma)[k] = std::sqrt(std::max(var, 0.0));
    }
  }
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

// The solution's epochs from `run`, into `output`, or into the returned solution when `output`
// is empty (the solution then holds only the GNSS bookkeeping).
NavSolution outputSolution(const FgoGraph& graph, const std::string& estimator,
                           const std::function<void(const FgoEpochFn&, const FgoScaleFn&)>& run,
                           const FgoEpochFn& output, const FgoScaleFn& scale_output) {
  NavSolution sol;
  sol.estimator = estimator;
  if (output) {
    run(output, graph.estimatesOdometerScale() ? scale_output : FgoScaleFn{});
  } else {
    // Every sample after the initial state (placed nodes: the samples held, else known later).
    const size_t n_out = !graph.placing() ? graph.sampleCount() - graph.firstSample() + 1
                                          : graph.problem().imu.size() + 1;
    sol.states.reserve(n_out);
    sol.gyro_bias_rad_s.reserve(n_out);
    sol.accel_bias_m_s2.reserve(n_out);
    const bool imu_scale = graph.estimatesImuScale();  // scale series only then (imu_errors.txt)
    FgoScaleFn scale;
    if (graph.estimatesOdometerScale()) {
      scale = [&](const OdometerScaleEstimate& k) {
        sol.odometer_scale.push_back(k.scale);
        sol.odometer_scale_std.push_back(k.std);
      };
    }
    run(
        [&](const NavState& s, const PvaSigma* sigma, const ImuErrorEstimate& e) {
          sol.states.push_back(s);
          sol.gyro_bias_rad_s.push_back(e.gyro_bias_rad_s);
          sol.accel_bias_m_s2.push_back(e.accel_bias_m_s2);
          if (imu_scale) {
            sol.gyro_scale.push_back(e.gyro_scale);
            sol.accel_scale.push_back(e.accel_scale);
          }
          if (sigma) sol.sigma.push_back(*sigma);
        },
        scale);
  }
  sol.gnss_withheld = graph.gnssWithheld();
  return sol;
}

bool allFinite(const NodeValue& x) {
  return x.p_w.allFinite() && x.q_wb.coeffs().allFinite() && x.v_w.allFinite() &&
         x.bg.allFinite() && x.ba.allFinite() && x.imu_scale.gyro.allFinite() &&
         x.imu_scale.accel.allFinite();
}

// The window estimator's output as the window goes: each node's causal value (or, fixed-lag,
// its value when it left the window) integrated over its interval once the interval's samples
// are there.
class WindowOutput final : public WindowListener {
 public:
  WindowOutput(const FgoGraph& graph, bool fixed_lag, const FgoEpochFn& output,
               const FgoScaleFn& scale_output)
      : graph_(graph),
        fixed_lag_(fixed_lag),
        out_(graph.frame(), graph.problem().initial.gnss_week, output, scale_output) {}
  void entered(size_t k, const NodeValue& x, const ImuSampleBuffer& samples) override {
    if (fixed_lag_) return;
    if (k > 0) emitInterval(k - 1, held_, samples);
    held_ = x;
  }
  void left(size_t k, const NodeValue& x, const ImuSampleBuffer& samples) override {
    if (fixed_lag_) emitInterval(k, x, samples);
  }
  void finished(const ImuSampleBuffer& samples) override {
    if (!fixed_lag_) emitInterval(graph_.nodeCount() - 1, held_, samples);
    out_.finish();
  }

 private:
  void emitInterval(size_t k, const NodeValue& x, const ImuSampleBuffer& samples) {
    NodeBlocks b;
    b.set(x);  // as a node block holds it: unit quaternion
    const NodeValue y = b.value();
    if (!allFinite(y)) {
      throw std::runtime_error("solveWindowFgo: node " + std::to_string(k) + " at t=" +
                               std::to_string(graph_.node(k).t_s) + " has a non-finite value");
    }
    out_.node(graph_.node(k).t_s, y, nullptr);
    for (size_t i = graph_.intervalBegin(k); i < graph_.intervalEnd(k); ++i)
      out_.sample(samples.at(i));
  }

  const FgoGraph& graph_;
  const bool fixed_lag_;
  OutputIntegrator out_;
  NodeValue held_;  // causal: the newest node's value, output with its interval
};

// The batch problem over all nodes of a window-initialized graph.
class BatchSolver {
 public:
  BatchSolver(FgoGraph& graph, const ImuPassFn& imu, const FgoOptions& options, FgoReport* rep);
  void solve();
  void cullRounds();
  void reintegrationRounds();
  ceres::Problem& problem() { return prob_; }

 private:
  static ceres::Problem::Options problemOptions();
  // Intervals whose node bias moved far from the preintegration's linearization.
  std::vector<size_t> movedIntervals() const;
  // Odometer / NHC factors of every node, the scale's walk and prior (vehicle aiding only).
  void addVehicleFactors();
  // The IMU scale factors' Gauss-Markov factors and prior (when the graph estimates them).
  void addImuScaleFactors();

  FgoGraph& graph_;
  const ImuPassFn& imu_;
  const FgoOptions& options_;
  FgoReport& rep_;
  const size_t n_;
  ceres::Problem prob_;
  ceres::Solver::Options so_;
  std::vector<PreintegrationFactor*> pfs_;
  std::vector<std::vector<std::pair<ceres::ResidualBlockId, size_t>>> gnss_;  // per node: (id, fix)
  bool first_ = true;
};

ceres::Problem::Options BatchSolver::problemOptions() {
  ceres::Problem::Options po;
  po.enable_fast_removal = true;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return po;
}

std::vector<size_t> BatchSolver::movedIntervals() const {
  std::vector<size_t> moved;
  for (size_t k = 0; k + 1 < n_; ++k) {
    if (graph_.biasMovedFar(k)) moved.push_back(k);
  }
  return moved;
}

BatchSolver::BatchSolver(FgoGraph& graph, const ImuPassFn& imu, const FgoOptions& options,
                         FgoReport* rep)
    : graph_(graph),
      imu_(imu),
      options_(options),
      rep_(*rep),
      n_(graph.nodeCount()),
      prob_(problemOptions()),
      pfs_(n_ > 0 ? n_ - 1 : 0),
      gnss_(n_) {
  for (size_t k = 0; k < n_; ++k) graph_.addNodeBlocks(&prob_, k);
  prob_.AddResidualBlock(graph_.makeInitialPrior(), nullptr, graph_.nodeBlocks(0));
  const std::vector<size_t> moved = movedIntervals();
  graph_.preintegrateFromPass(imu_, moved);
  rep_.reintegrations += static_cast<int>(moved.size());
  for (size_t k = 0; k + 1 < n_; ++k) {
    pfs_[k] = graph_.makePreintegrationFactor(k);
    prob_.AddResidualBlock(pfs_[k], nullptr, graph_.preintegrationBlocks(k));
    prob_.AddResidualBlock(graph_.makeBiasFactor(k), nullptr, graph_.biasBlocks(k));
  }
  addImuScaleFactors();
  addVehicleFactors();
  for (size_t k = 0; k < n_; ++k) {
    for (size_t fix : graph_.node(k).gnss) {
      gnss_[k].emplace_back(prob_.AddResidualBlock(graph_.makeGnssFactor(fix), graph_.gnssLoss(),
                                                   graph_.poseBlocks(k)),
                            fix);
    }
  }
  so_.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so_.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  so_.max_num_iterations = options.max_iterations;
  so_.initial_trust_region_radius = options.initial_trust_region_radius;  // see sliding_window.cpp
  so_.num_threads = options.num_threads;
  so_.logging_type = ceres::SILENT;
}

void BatchSolver::addImuScaleFactors() {
  if (!graph_.estimatesImuScale() || n_ == 0) return;
  prob_.AddResidualBlock(graph_.makeImuScalePrior(), nullptr,
                         {graph_.blocks(0).sg, graph_.blocks(0).sa});
  for (size_t k = 0; k + 1 < n_; ++k) {
    prob_.AddResidualBlock(graph_.makeImuScaleFactor(k), nullptr, graph_.imuScaleBlocks(k));
  }
}

void BatchSolver::addVehicleFactors() {
  if (graph_.estimatesOdometerScale()) {
    prob_.AddResidualBlock(graph_.makeScalePrior(), nullptr, {graph_.blocks(0).s});
    for (size_t k = 0; k + 1 < n_; ++k) {
      prob_.AddResidualBlock(graph_.makeScaleWalkFactor(k), nullptr, graph_.scaleWalkBlocks(k));
    }
  }
  for (size_t k = 1; k < n_; ++k) {
    if (VehicleVelocityFactor* f = graph_.makeVehicleFactor(k)) {
      prob_.AddResidualBlock(f, nullptr, graph_.vehicleBlocks(k, *f));
      ++rep_.vehicle_factors;
    }
  }
}

void BatchSolver::solve() {
  ceres::Solver::Summary summary;
  ceres::Solve(so_, &prob_, &summary);
  if (summary.termination_type == ceres::FAILURE) {
    throw std::runtime_error("solveBatchFgo: Ceres failed: " + summary.message);
  }
  graph_.requireFinite(0, n_, "solveBatchFgo (solve " + std::to_string(rep_.solves + 1) + ")");
  if (first_) rep_.initial_cost = summary.initial_cost;
  first_ = false;
  rep_.final_cost = summary.final_cost;
  ++rep_.solves;
  rep_.iterations += static_cast<int>(summary.iterations.size());
}

void BatchSolver::cullRounds() {
  for (int round = 0; round < options_.culling_rounds; ++round) {
    // Candidates first: when more than max_cull_fraction of the fixes fail, the graph (not the
    // fixes) is wrong, and culling would only hide it.
    std::vector<std::pair<size_t, size_t>> bad;  // (node, position in gnss_[node])
    std::vector<double> bad_chi2;
    for (size_t k = 0; k < n_; ++k) {
      for (size_t i = 0; i < gnss_[k].size(); ++i) {
        const double chi2 = graph_.gnssChi2(gnss_[k][i].second, k);
        if (chi2 > options_.chi2_threshold) {
          bad.emplace_back(k, i);
          bad_chi2.push_back(chi2);
        }
      }
    }
    if (bad.empty()) break;
    if (bad.size() > options_.max_cull_fraction * static_cast<double>(graph_.fixCount())) {
      rep_.cull_refused = static_cast<int>(bad.size());
      break;
    }
    for (size_t b = bad.size(); b-- > 0;) {  // back to front keeps positions valid
      auto& list = gnss_[bad[b].first];
      rep_.culled_times_s.push_back(graph_.fix(list[bad[b].second].second).fix.t_s);
      rep_.culled_chi2.push_back(bad_chi2[b]);
      prob_.RemoveResidualBlock(list[bad[b].second].first);
      list.erase(list.begin() + static_cast<long>(bad[b].second));
    }
    rep_.gnss_culled += static_cast<int>(bad.size());
    solve();
  }
}

void BatchSolver::reintegrationRounds() {
  for (int round = 0; round < options_.max_reintegration_rounds; ++round) {
    const std::vector<size_t> moved = movedIntervals();
    graph_.preintegrateFromPass(imu_, moved);
    for (size_t k : moved) pfs_[k]->refresh();
    rep_.reintegrations += static_cast<int>(moved.size());
    if (moved.empty()) break;
    solve();
  }
}

// Initial values: a fixed-lag sliding-window pass that solves every batch_init_stride nodes
// (counts of its culling are not kept: the batch re-decides every fix) and places the nodes as
// it goes (its options differ from the batch's in window fields only, which the layout does not
// read). Every node and interval's preintegration stays.
void initializeByWindow(FgoGraph& graph, const ImuPassFn& imu, const FgoOptions& options,
                        FgoReport* rep) {
  FgoOptions init = options;
  init.window_solve_stride = options.batch_init_stride;
  init.window_nodes = std::max(options.window_nodes, 2 * options.batch_init_stride);
  graph.setOptions(init);
  FgoReport wrep;
  runSlidingWindow(graph, imu, &wrep, true);
  rep->reintegrations += wrep.reintegrations;
  graph.setOptions(options);
  graph.requireFinite(0, graph.nodeCount(), "solveBatchFgo (window initialization)");
}

}  // namespace

ImuPassFn seriesPass(const ImuSeries& imu) {
  return [&imu](const ImuBlockFn& block) { block(imu); };
}

NavSolution solveWindowFgo(const EstimationProblem& problem, const FgoOptions& options,
                           FgoReport* report, const FgoEpochFn& output,
                           const FgoScaleFn& scale_output) {
  return solveWindowFgo(problem, seriesPass(problem.imu), options, report, output, scale_output);
}

NavSolution solveWindowFgo(const EstimationProblem& problem, const ImuPassFn& imu,
                           const FgoOptions& options, FgoReport* report, const FgoEpochFn& output,
                           const FgoScaleFn& scale_output) {
  FgoReport local;
  FgoReport& rep = report ? *report : local;
  const auto t0 = std::chrono::steady_clock::now();
  FgoGraph graph(problem, options, PlaceNodesDuringPass{});  // one read of the IMU
  NavSolution sol = outputSolution(
      graph, "fgo-window",
      [&](const FgoEpochFn& out, const FgoScaleFn& scale) {
        WindowOutput listener(graph, options.window_fixed_lag_output, out, scale);
        runSlidingWindow(graph, imu, &rep, false, &listener);
      },
      output, scale_output);
  rep.window_time_s = secondsSince(t0);  // with the output, written as the window goes
  rep.nodes = static_cast<int>(graph.nodeCount());
  rep.gnss_factors = static_cast<int>(graph.fixCount());
  sol.gnss_used = rep.gnss_factors - rep.gnss_culled;
  sol.gnss_rejected = rep.gnss_culled;
  sol.vehicle_used = rep.vehicle_factors;
  rep.summary = fmt::format(
      "fgo-window: {} nodes, {} GNSS ({} culled), {} re-preintegrations, "
      "{} solves, {:.3f} s",
      rep.nodes, rep.gnss_factors, rep.gnss_culled, rep.reintegrations, rep.solves,
      rep.window_time_s);
  return sol;
}

NavSolution solveBatchFgo(const EstimationProblem& problem, const FgoOptions& options,
                          FgoReport* report, const FgoEpochFn& output,
                          const FgoScaleFn& scale_output) {
  return solveBatchFgo(problem, seriesPass(problem.imu), options, report, output, scale_output);
}

NavSolution solveBatchFgo(const EstimationProblem& problem, const ImuPassFn& imu,
                          const FgoOptions& options, FgoReport* report, const FgoEpochFn& output,
                          const FgoScaleFn& scale_output) {
  FgoReport local;
  FgoReport& rep = report ? *report : local;
  auto t0 = std::chrono::steady_clock::now();
  FgoGraph graph(problem, options, PlaceNodesDuringPass{});  // placed by the window pass
  initializeByWindow(graph, imu, options, &rep);
  rep.window_time_s = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  rep.nodes = static_cast<int>(graph.nodeCount());
  rep.gnss_factors = static_cast<int>(graph.fixCount());
  BatchSolver batch(graph, imu, options, &rep);
  batch.solve();
  batch.cullRounds();
  batch.reintegrationRounds();
  rep.batch_time_s = secondsSince(t0);

  std::vector<PvaSigma> sig;
  std::vector<double> scale_sig;
  if (options.compute_covariance) {
    t0 = std::chrono::steady_clock::now();
    sig = nodeSigmas(graph, batch.problem(), options.num_threads, &scale_sig, &rep);
    rep.covariance_time_s = secondsSince(t0);
  }
  t0 = std::chrono::steady_clock::now();
  NavSolution sol = outputSolution(
      graph, "fgo",
      [&](const FgoEpochFn& out, const FgoScaleFn& scale) {
        graph.outputPass(imu, sig, out, scale, scale_sig);
      },
      output, scale_output);
  rep.output_time_s = secondsSince(t0);
  sol.gnss_used = rep.gnss_factors - rep.gnss_culled;
  sol.gnss_rejected = rep.gnss_culled;
  sol.vehicle_used = rep.vehicle_factors;
  rep.summary = fmt::format(
      "fgo: {} nodes, {} GNSS ({} culled), {} re-preintegrations, {} solves / {} iterations, "
      "cost {:.4g} -> {:.4g}, window init {:.3f} s, batch {:.3f} s{}",
      rep.nodes, rep.gnss_factors, rep.gnss_culled, rep.reintegrations, rep.solves, rep.iterations,
      rep.initial_cost, rep.final_cost, rep.window_time_s, rep.batch_time_s,
      rep.cull_refused > 0 ? fmt::format(" (culling refused: {} fixes failed)", rep.cull_refused)
                           : std::string());
  return sol;
}

}  // namespace graftnav
