#include "graftnav/graph/fgo_graph.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/nav/mechanization.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

NodeValue NodeBlocks::value() const {
  NodeValue x;
  x.p_w = Eigen::Map<const Eigen::Vector3d>(p);
  x.q_wb = Eigen::Map<const Eigen::Quaterniond>(q);
  x.v_w = Eigen::Map<const Eigen::Vector3d>(v);
  x.bg = Eigen::Map<const Eigen::Vector3d>(bg);
  x.ba = Eigen::Map<const Eigen::Vector3d>(ba);
  return x;
}

void NodeBlocks::set(const NodeValue& x) {
  Eigen::Map<Eigen::Vector3d>{p} = x.p_w;
  Eigen::Map<Eigen::Quaterniond>{q} = x.q_wb.normalized();
  Eigen::Map<Eigen::Vector3d>{v} = x.v_w;
  Eigen::Map<Eigen::Vector3d>{bg} = x.bg;
  Eigen::Map<Eigen::Vector3d>{ba} = x.ba;
}

FgoGraph::FgoGraph(const EstimationProblem& problem, const FgoOptions& options)
    : problem_(problem), options_(options), frame_(problem.initial.pos) {
  std::string err;
  if (!options_.validate(&err)) throw std::invalid_argument("FgoGraph: " + err);
  if (problem.imu.size() < 2) throw std::invalid_argument("FgoGraph: fewer than 2 IMU samples");
  const ImuProfile& prof = problem.imu_profile;
  noise_.arw_rad_sqrt_s = std::max(prof.arw_rad_sqrt_s, options_.min_arw_rad_sqrt_s);
  noise_.vrw_m_s_sqrt_s = std::max(prof.vrw_m_s_sqrt_s, options_.min_vrw_m_s_sqrt_s);
  gyro_process_.sigma = std::max(prof.gyro_bias_instability_rad_s, options_.min_gyro_bias_std_rad_s);
  gyro_process_.tau_s = prof.gyro_bias_corr_time_s;
  accel_process_.sigma =
      std::max(prof.accel_bias_instability_m_s2, options_.min_accel_bias_std_m_s2);
  accel_process_.tau_s = prof.accel_bias_corr_time_s;
  if (options_.robust_loss == "huber") {
    loss_ = std::make_unique<ceres::HuberLoss>(options_.robust_loss_scale);
  } else if (options_.robust_loss == "cauchy") {
    loss_ = std::make_unique<ceres::CauchyLoss>(options_.robust_loss_scale);
  }
  buildNodes();
  blocks_.resize(nodes_.size());
  pre_.resize(nodes_.size() > 0 ? nodes_.size() - 1 : 0);
  gravity_point_.resize(pre_.size());
  initializeFirstNode();
}

void FgoGraph::buildNodes() {
  const ImuSeries& imu = problem_.imu;
  const double t0 = problem_.initial.t_s;
  first_sample_ = static_cast<size_t>(
      std::upper_bound(imu.begin(), imu.end(), t0 + 1e-6,
                       [](double t, const ImuSample& s) { return t < s.t_s; }) -
      imu.begin());
  if (first_sample_ >= imu.size()) {
    throw std::invalid_argument("FgoGraph: initial state at t=" + std::to_string(t0) +
                                " is after the last IMU sample");
  }
  // Index of the sample whose end time is nearest t (within [first_sample_, size)).
  auto nearestSample = [&](double t) {
    auto it = std::lower_bound(imu.begin() + first_sample_, imu.end(), t,
                               [](const ImuSample& s, double tt) { return s.t_s < tt; });
    size_t idx = static_cast<size_t>(it - imu.begin());
    if (idx >= imu.size()) idx = imu.size() - 1;
    if (idx > first_sample_ && std::abs(imu[idx - 1].t_s - t) < std::abs(imu[idx].t_s - t)) --idx;
    return idx;
  };

  // GNSS epochs used (outside outages, inside the IMU span, not at the initial epoch).
  std::vector<std::pair<size_t, size_t>> gnss_at_sample;  // (sample index, fix index)
  for (const GnssFix& f : problem_.gnss) {
    bool withheld = false;
    for (const TimeWindow& w : problem_.outages) withheld = withheld || w.contains(f.t_s);
    if (withheld) {
      ++gnss_withheld_;
      continue;
    }
    if (f.t_s <= t0 + 1e-6 || f.t_s > imu.back().t_s + 0.5 * imu.back().dt_s) continue;
    const size_t idx = nearestSample(f.t_s);
    if (std::abs(imu[idx].t_s - f.t_s) > imu[idx].dt_s) continue;  // IMU gap at the fix
    GnssObservation obs;
    obs.fix = f;
    obs.z_w = frame_.toLocal(f.pos);
    Eigen::Vector3d std_ned = f.std_ned_m.cwiseMax(options_.gnss_min_std_m);
    const Eigen::Matrix3d C_wn = frame_.C_nw(f.pos).transpose();
    const Eigen::Matrix3d cov_w = C_wn * std_ned.cwiseAbs2().asDiagonal() * C_wn.transpose();
    obs.sqrt_info_w = Eigen::LLT<Eigen::Matrix3d>(cov_w).matrixL().solve(Eigen::Matrix3d::Identity());
    obs.dt_s = f.t_s - imu[idx].t_s;
    gnss_at_sample.emplace_back(idx, fixes_.size());
    fixes_.push_back(obs);
  }
  std::sort(gnss_at_sample.begin(), gnss_at_sample.end());

  // Node sample indices: GNSS nodes, then fill gaps every max_node_spacing_s.
  std::vector<size_t> anchors;
  for (const auto& g : gnss_at_sample) {
    if (anchors.empty() || anchors.back() != g.first) anchors.push_back(g.first);
  }
  if (anchors.empty() || anchors.back() != imu.size() - 1) anchors.push_back(imu.size() - 1);

  GraphNode n0;
  n0.t_s = t0;
  n0.sample_end = first_sample_;
  nodes_.push_back(n0);
  const double spacing = options_.max_node_spacing_s;
  size_t gi = 0;
  for (size_t a : anchors) {
    const double t_prev = nodes_.back().t_s;
    const double t_a = imu[a].t_s;
    const int n_sub = static_cast<int>(std::ceil((t_a - t_prev) / spacing - 0.25));
    for (int m = 1; m < n_sub; ++m) {
      const size_t idx = nearestSample(t_prev + (t_a - t_prev) * m / n_sub);
      if (idx + 1 > nodes_.back().sample_end && idx < a) {
        GraphNode n;
        n.t_s = imu[idx].t_s;
        n.sample_end = idx + 1;
        nodes_.push_back(n);
      }
    }
    if (a + 1 <= nodes_.back().sample_end) continue;  // at or before the previous node
    GraphNode n;
    n.t_s = t_a;
    n.sample_end = a + 1;
    while (gi < gnss_at_sample.size() && gnss_at_sample[gi].first <= a) {
      if (gnss_at_sample[gi].first == a) n.gnss.push_back(gnss_at_sample[gi].second);
      ++gi;
    }
    nodes_.push_back(n);
  }
}

void FgoGraph::initializeFirstNode() {
  NodeValue x;
  frame_.fromNavState(problem_.initial, &x.p_w, &x.v_w, &x.q_wb);
  blocks_[0].set(x);
}

ImuPreintegration& FgoGraph::preintegrate(size_t k) {
  const NodeValue x = blocks_[k].value();
  if (!pre_[k]) pre_[k] = std::make_unique<ImuPreintegration>(x.bg, x.ba, noise_);
  pre_[k]->reintegrate(problem_.imu, nodes_[k].sample_end, nodes_[k + 1].sample_end, x.bg, x.ba);
  gravity_point_[k] = x.p_w;
  return *pre_[k];
}

bool FgoGraph::biasMovedFar(size_t k) const {
  const NodeBlocks& b = blocks_[k];
  const ImuPreintegration& pre = *pre_[k];
  return (Eigen::Map<const Eigen::Vector3d>(b.bg) - pre.bgLin()).norm() >
             options_.reintegrate_gyro_bias_rad_s ||
         (Eigen::Map<const Eigen::Vector3d>(b.ba) - pre.baLin()).norm() >
             options_.reintegrate_accel_bias_m_s2;
}

PreintegrationFactor* FgoGraph::makePreintegrationFactor(size_t k) const {
  const Eigen::Vector3d w =
      options_.earth_rotation ? frame_.omega_ie_w() : Eigen::Vector3d::Zero().eval();
  // Gravity linearized at node k's position when the interval was preintegrated.
  return new PreintegrationFactor(pre_[k].get(), w, frame_.linearGravity(gravity_point_[k]));
}

BiasFactor* FgoGraph::makeBiasFactor(size_t k) const {
  return new BiasFactor(gyro_process_, accel_process_, nodes_[k + 1].t_s - nodes_[k].t_s);
}

GnssPositionFactor* FgoGraph::makeGnssFactor(size_t fix) const {
  const GnssObservation& o = fixes_[fix];
  return new GnssPositionFactor(o.z_w, o.sqrt_info_w, problem_.lever_arm_b_m, o.dt_s);
}

NodePriorFactor* FgoGraph::makeInitialPrior() const {
  NodeValue x0;  // the given initial state, whatever node 0's current value
  frame_.fromNavState(problem_.initial, &x0.p_w, &x0.v_w, &x0.q_wb);
  const PvaSigma& s = problem_.initial_sigma;
  auto pick = [&](int i, double dflt) { return s(i) >= 0.0 ? std::max(s(i), 1e-6) : dflt; };
  Eigen::Vector3d sp, sv, sa;
  for (int i = 0; i < 3; ++i) {
    sp(i) = pick(i, options_.initial_position_std_m);
    sv(i) = pick(3 + i, options_.initial_velocity_std_m_s);
    sa(i) = pick(6 + i, options_.initial_attitude_std_rad);
  }
  const ImuProfile& prof = problem_.imu_profile;
  const double sbg = std::max(prof.gyro_bias_initial_std_rad_s > 0 ? prof.gyro_bias_initial_std_rad_s
                                                                   : prof.gyro_bias_instability_rad_s,
                              options_.min_gyro_bias_std_rad_s);
  const double sba =
      std::max(prof.accel_bias_initial_std_m_s2 > 0 ? prof.accel_bias_initial_std_m_s2
                                                    : prof.accel_bias_instability_m_s2,
               options_.min_accel_bias_std_m_s2);
  // NED sigmas to w (the origin's NED, so identity at node 0) and attitude about NED to the
  // body-frame tangent: dtheta_n = C_nb dtheta_b.
  const Eigen::Matrix3d C_bn = problem_.initial.q_nb.toRotationMatrix().transpose();
  const Eigen::Matrix3d cov_att_b = C_bn * sa.cwiseAbs2().asDiagonal() * C_bn.transpose();
  NodePriorFactor::Matrix15d S = NodePriorFactor::Matrix15d::Zero();
  S.block<3, 3>(0, 0) = sp.cwiseInverse().asDiagonal();
  S.block<3, 3>(3, 3) =
      Eigen::LLT<Eigen::Matrix3d>(cov_att_b).matrixL().solve(Eigen::Matrix3d::Identity());
  S.block<3, 3>(6, 6) = sv.cwiseInverse().asDiagonal();
  S.block<3, 3>(9, 9) = Eigen::Matrix3d::Identity() / sbg;
  S.block<3, 3>(12, 12) = Eigen::Matrix3d::Identity() / sba;
  return new NodePriorFactor(x0, S, NodePriorFactor::Vector15d::Zero());
}

void FgoGraph::addNodeBlocks(ceres::Problem* problem, size_t k) const {
  NodeBlocks& b = const_cast<NodeBlocks&>(blocks_[k]);
  problem->AddParameterBlock(b.p, 3);
  problem->AddParameterBlock(b.q, 4, quaternionManifold());
  problem->AddParameterBlock(b.v, 3);
  problem->AddParameterBlock(b.bg, 3);
  problem->AddParameterBlock(b.ba, 3);
}

std::vector<double*> FgoGraph::preintegrationBlocks(size_t k) {
  NodeBlocks& i = blocks_[k];
  NodeBlocks& j = blocks_[k + 1];
  return {i.p, i.q, i.v, i.bg, i.ba, j.p, j.q, j.v};
}

std::vector<double*> FgoGraph::biasBlocks(size_t k) {
  return {blocks_[k].bg, blocks_[k].ba, blocks_[k + 1].bg, blocks_[k + 1].ba};
}

std::vector<double*> FgoGraph::poseBlocks(size_t k) {
  return {blocks_[k].p, blocks_[k].q, blocks_[k].v};
}

std::vector<double*> FgoGraph::nodeBlocks(size_t k) {
  NodeBlocks& b = blocks_[k];
  return {b.p, b.q, b.v, b.bg, b.ba};
}

double FgoGraph::gnssChi2(size_t fix, size_t node) {
  std::unique_ptr<GnssPositionFactor> f(makeGnssFactor(fix));
  const std::vector<double*> blocks = poseBlocks(node);
  Eigen::Vector3d r;
  f->Evaluate(blocks.data(), r.data(), nullptr);
  return r.squaredNorm();
}

void FgoGraph::requireFinite(size_t begin, size_t end, const std::string& stage) const {
  end = std::min(end, blocks_.size());
  for (size_t k = begin; k < end; ++k) {
    const NodeBlocks& b = blocks_[k];
    const char* bad = nullptr;
    auto finite = [](const double* x, int n) {
      for (int i = 0; i < n; ++i) {
        if (!std::isfinite(x[i])) return false;
      }
      return true;
    };
    if (!finite(b.p, 3)) bad = "position";
    else if (!finite(b.q, 4)) bad = "attitude";
    else if (!finite(b.v, 3)) bad = "velocity";
    else if (!finite(b.bg, 3)) bad = "gyro bias";
    else if (!finite(b.ba, 3)) bad = "accel bias";
    if (bad == nullptr) continue;
    std::string msg = stage + ": node " + std::to_string(k) + " at t=" +
                      std::to_string(nodes_[k].t_s) + " has a non-finite " + bad;
    if (k > 0 && hasPreintegration(k - 1)) {
      msg += " (preintegration from node " + std::to_string(k - 1) + " at t=" +
             std::to_string(nodes_[k - 1].t_s) + " over " + std::to_string(pre_[k - 1]->dt_s()) +
             " s, " + std::to_string(nodes_[k].gnss.size()) + " GNSS fixes on the node)";
    }
    throw std::runtime_error(msg);
  }
}

void FgoGraph::predictNode(size_t k) {
  const NodeValue x = blocks_[k - 1].value();
  std::unique_ptr<PreintegrationFactor> f(makePreintegrationFactor(k - 1));
  NodeValue y;
  f->predict(x.p_w, x.q_wb, x.v_w, x.bg, x.ba, &y.p_w, &y.q_wb, &y.v_w);
  y.bg = x.bg;
  y.ba = x.ba;
  blocks_[k].set(y);
}

NavSolution FgoGraph::integrateOutput(const std::string& estimator,
                                      const std::vector<PvaSigma>& sigma_nodes) const {
  NavSolution sol;
  sol.estimator = estimator;
  const size_t n_out = problem_.imu.size() - first_sample_ + 1;
  sol.states.reserve(n_out);
  sol.gyro_bias_rad_s.reserve(n_out);
  sol.accel_bias_m_s2.reserve(n_out);
  if (!sigma_nodes.empty()) sol.sigma.reserve(n_out);
  integrateOutput(sigma_nodes, [&](const NavState& s, const PvaSigma* sigma, const Eigen::Vector3d& bg,
                                   const Eigen::Vector3d& ba) {
    sol.states.push_back(s);
    sol.gyro_bias_rad_s.push_back(bg);
    sol.accel_bias_m_s2.push_back(ba);
    if (sigma) sol.sigma.push_back(*sigma);
  });
  sol.gnss_withheld = gnss_withheld_;
  return sol;
}

void FgoGraph::integrateOutput(const std::vector<PvaSigma>& sigma_nodes, const FgoEpochFn& output) const {
  const ImuSeries& imu = problem_.imu;
  const bool with_sigma = !sigma_nodes.empty();
  // Each epoch is held back by one: a node's own epoch, already output as the end of the
  // previous interval, is replaced by the node estimate so the solution passes exactly through
  // the optimized nodes.
  struct Pending {
    NavState state;
    Eigen::Vector3d bg, ba;
    size_t node = 0;
  } pending;
  auto emit = [&]() {
    output(pending.state, with_sigma ? &sigma_nodes[pending.node] : nullptr, pending.bg, pending.ba);
  };
  const NodeValue x0 = blocks_[0].value();
  NavState s0 = frame_.toNavState(nodes_[0].t_s, x0.p_w, x0.v_w, x0.q_wb);
  s0.gnss_week = problem_.initial.gnss_week;
  Strapdown sd(s0);
  pending = {s0, x0.bg, x0.ba, 0};
  for (size_t k = 0; k < nodes_.size(); ++k) {
    const NodeValue x = blocks_[k].value();
    if (k > 0) {
      NavState s = frame_.toNavState(nodes_[k].t_s, x.p_w, x.v_w, x.q_wb);
      s.gnss_week = s0.gnss_week;
      sd.setState(s);
      pending = {s, x.bg, x.ba, k};
    }
    const size_t end = (k + 1 < nodes_.size()) ? nodes_[k + 1].sample_end : imu.size();
    for (size_t i = nodes_[k].sample_end; i < end; ++i) {
      ImuSample c = imu[i];
      c.dtheta_rad -= x.bg * c.dt_s;
      c.dvel_m_s -= x.ba * c.dt_s;
      sd.step(c);
      emit();
      pending = {sd.state(), x.bg, x.ba, k};
    }
  }
  emit();
}

}  // namespace graftnav
