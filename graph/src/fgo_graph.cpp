#include "graftnav/graph/fgo_graph.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "graftnav/graph/fgo_solver.h"
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
  x.odometer_scale = s[0];
  x.imu_scale.gyro = Eigen::Map<const Eigen::Vector3d>(sg);
  x.imu_scale.accel = Eigen::Map<const Eigen::Vector3d>(sa);
  return x;
}

void NodeBlocks::set(const NodeValue& x) {
  Eigen::Map<Eigen::Vector3d>{p} = x.p_w;
  Eigen::Map<Eigen::Quaterniond>{q} = x.q_wb.normalized();
  Eigen::Map<Eigen::Vector3d>{v} = x.v_w;
  Eigen::Map<Eigen::Vector3d>{bg} = x.bg;
  Eigen::Map<Eigen::Vector3d>{ba} = x.ba;
  s[0] = x.odometer_scale;
  Eigen::Map<Eigen::Vector3d>{sg} = x.imu_scale.gyro;
  Eigen::Map<Eigen::Vector3d>{sa} = x.imu_scale.accel;
}

FgoGraph::FgoGraph(const EstimationProblem& problem, const FgoOptions& options)
    : problem_(problem), options_(options), frame_(problem.initial.pos), memory_imu_(&problem.imu) {
  setUp();
  layout_ = buildNodeLayout(problem_, frame_, options_, seriesPass(problem.imu));
  addNodeStorage();
}

FgoGraph::FgoGraph(const EstimationProblem& problem, const FgoOptions& options,
                   const ImuPassFn& imu)
    : problem_(problem), options_(options), frame_(problem.initial.pos) {
  setUp();
  layout_ = buildNodeLayout(problem_, frame_, options_, imu);
  addNodeStorage();
}

FgoGraph::FgoGraph(const EstimationProblem& problem, const FgoOptions& options,
                   PlaceNodesDuringPass)
    : problem_(problem), options_(options), frame_(problem.initial.pos) {
  setUp();
  builder_ = std::make_unique<NodeLayoutBuilder>(problem_, frame_, options_, &layout_);
}

void FgoGraph::setUp() {
  std::string err;
  if (!options_.validate(&err)) throw std::invalid_argument("FgoGraph: " + err);
  const ImuProfile& prof = problem_.imu_profile;
  noise_.arw_rad_sqrt_s = std::max(prof.arw_rad_sqrt_s, options_.min_arw_rad_sqrt_s);
  noise_.vrw_m_s_sqrt_s = std::max(prof.vrw_m_s_sqrt_s, options_.min_vrw_m_s_sqrt_s);
  gyro_process_.sigma =
      std::max(prof.gyro_bias_instability_rad_s, options_.min_gyro_bias_std_rad_s);
  gyro_process_.tau_s = prof.gyro_bias_corr_time_s;
  accel_process_.sigma =
      std::max(prof.accel_bias_instability_m_s2, options_.min_accel_bias_std_m_s2);
  accel_process_.tau_s = prof.accel_bias_corr_time_s;
  aiding_ = problem_.aiding;
  if (aiding_.any()) {
    aiding_.validate();
    C_vb_ = aiding_.C_vb();
  }
  imu_scale_ = options_.imu_scale_states == ImuScaleStates::kOn ||
               (options_.imu_scale_states == ImuScaleStates::kWithVehicleAiding && aiding_.any());
  gyro_scale_process_.sigma = std::max(prof.gyro_scale_std, options_.min_imu_scale_std);
  gyro_scale_process_.tau_s = prof.scale_corr_time_s;
  accel_scale_process_.sigma = std::max(prof.accel_scale_std, options_.min_imu_scale_std);
  accel_scale_process_.tau_s = prof.scale_corr_time_s;
  switch (options_.robust_loss) {
    case RobustLoss::kHuber:
      loss_ = std::make_unique<ceres::HuberLoss>(options_.robust_loss_scale);
      break;
    case RobustLoss::kCauchy:
      loss_ = std::make_unique<ceres::CauchyLoss>(options_.robust_loss_scale);
      break;
    case RobustLoss::kNone:
      break;
  }
}

void FgoGraph::addNodeStorage() {
  const bool first = blocks_.empty() && layout_.nodes_base == 0;
  while (layout_.nodes_base + blocks_.size() < layout_.nodeCount()) {
    blocks_.emplace_back();
    pre_.emplace_back();
    gravity_point_.emplace_back(Eigen::Vector3d::Zero());
    vehicle_obs_.emplace_back();
  }
  if (first && !blocks_.empty()) initializeFirstNode();
}

void FgoGraph::placeSample(const ImuSample& s) {
  builder_->add(s);
  addNodeStorage();
}

void FgoGraph::finishPlacing() {
  builder_->finish();
  builder_.reset();
  addNodeStorage();
}

void FgoGraph::forgetBefore(size_t k) {
  layout_.forgetBefore(k);
  while (blocks_.size() > layout_.nodes.size()) {
    blocks_.pop_front();
    pre_.pop_front();
    gravity_point_.pop_front();
    vehicle_obs_.pop_front();
  }
}

void FgoGraph::initializeFirstNode() {
  NodeValue x;
  frame_.fromNavState(problem_.initial, &x.p_w, &x.v_w, &x.q_wb);
  blocks(0).set(x);
}

ImuPreintegration& FgoGraph::preintegrate(size_t k) {
  if (!memory_imu_) throw std::logic_error("FgoGraph::preintegrate: no samples in memory");
  const NodeValue x = blocks(k).value();
  const size_t begin = intervalBegin(k), end = intervalEnd(k);
  if (begin >= end || end > memory_imu_->size()) {
    throw std::invalid_argument("FgoGraph::preintegrate: interval " + std::to_string(k) +
                                " is outside the samples");
  }
  return preintegrateAt(k, x, memory_imu_->data() + begin, end - begin,
                        begin > 0 ? &(*memory_imu_)[begin - 1] : nullptr);
}

ImuPreintegration& FgoGraph::preintegrate(size_t k, const ImuSampleBuffer& samples) {
  const size_t begin = intervalBegin(k), end = intervalEnd(k);
  if (begin >= end) {
    throw std::invalid_argument("FgoGraph::preintegrate: interval " + std::to_string(k) +
                                " is empty");
  }
  const ImuSample* first = &samples.at(begin);
  samples.at(end - 1);  // the whole interval is held (contiguous storage)
  return preintegrateAt(k, blocks(k).value(), first, end - begin,
                        begin > 0 ? &samples.at(begin - 1) : nullptr);
}

ImuPreintegration& FgoGraph::preintegrateAt(size_t k, const NodeValue& x, const ImuSample* samples,
                                            size_t count, const ImuSample* before) {
  std::unique_ptr<ImuPreintegration>& p = pre(k);
  if (!p) p = std::make_unique<ImuPreintegration>(x.bg, x.ba, noise_);
  if (imu_scale_) {
    p->reintegrate(samples, count, before, x.bg, x.ba, x.imu_scale);
  } else {
    p->reintegrate(samples, count, before, x.bg, x.ba);
  }
  gravity_point_[k - layout_.nodes_base] = x.p_w;
  return *p;
}

void FgoGraph::preintegrateFromPass(const ImuPassFn& imu, const std::vector<size_t>& intervals) {
  if (intervals.empty()) return;
  ImuSampleBuffer buffer;
  size_t next = 0;
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      if (next == intervals.size()) return;
      buffer.push(s);
      while (next < intervals.size() && intervalEnd(intervals[next]) <= buffer.end()) {
        preintegrate(intervals[next++], buffer);
      }
      if (next < intervals.size()) {  // keep from the next interval's coning memory on
        const size_t b = intervalBegin(intervals[next]);
        buffer.dropBefore(b > 0 ? b - 1 : 0);
      }
    }
  });
  if (next != intervals.size()) {
    throw std::runtime_error("FgoGraph: the IMU pass ended before interval " +
                             std::to_string(intervals[next]) +
                             " (fewer samples than the layout's)");
  }
}

bool FgoGraph::biasMovedFar(size_t k) const {
  const NodeBlocks& b = blocks(k);
  const ImuPreintegration& pre = *this->pre(k);
  return (Eigen::Map<const Eigen::Vector3d>(b.bg) - pre.bgLin()).norm() >
             options_.reintegrate_gyro_bias_rad_s ||
         (Eigen::Map<const Eigen::Vector3d>(b.ba) - pre.baLin()).norm() >
             options_.reintegrate_accel_bias_m_s2;
}

PreintegrationFactor* FgoGraph::makePreintegrationFactor(size_t k) const {
  const Eigen::Vector3d w =
      options_.earth_rotation ? frame_.omega_ie_w() : Eigen::Vector3d::Zero().eval();
  // Gravity linearized at node k's position when the interval was preintegrated.
  return new PreintegrationFactor(pre(k).get(), w,
                                  frame_.linearGravity(gravity_point_[k - layout_.nodes_base]));
}

BiasFactor* FgoGraph::makeBiasFactor(size_t k) const {
  return new BiasFactor(gyro_process_, accel_process_, node(k + 1).t_s - node(k).t_s);
}

GnssPositionFactor* FgoGraph::makeGnssFactor(size_t fix) const {
  const GnssObservation& o = layout_.fix(fix);
  return new GnssPositionFactor(o.z_w, o.sqrt_info_w, problem_.lever_arm_b_m, o.dt_s);
}

void FgoGraph::observeVehicle(size_t k, const ImuSampleBuffer& samples) {
  if (!aiding_.any() || k == 0) return;
  const ImuSample& s = samples.at(node(k).sample_end - 1);  // the sample ending at the node
  VehicleObservation& o = vehicle_obs_[k - layout_.nodes_base];
  o.omega_raw_b = s.dtheta_rad / s.dt_s;
  o.row_std_m_s = aiding_.rowStd_m_s();
  if (aiding_.odometer.enabled) {
    if (!odometer_) {
      odometer_ = std::make_unique<OdometerInterpolator>(problem_.openOdometer(),
                                                         aiding_.odometer.max_gap_s);
    }
    o.has_speed = odometer_->at(node(k).t_s, &o.speed_m_s);
  }
}

VehicleVelocityFactor* FgoGraph::makeVehicleFactor(size_t k) const {
  if (!aiding_.any() || k == 0) return nullptr;
  const VehicleObservation& o = vehicle_obs_[k - layout_.nodes_base];
  if (o.rows() == 0) return nullptr;
  return new VehicleVelocityFactor(o, C_vb_, aiding_.odometer.lever_arm_b_m, frame_.omega_ie_w(),
                                   estimatesOdometerScale());
}

OdometerScaleWalkFactor* FgoGraph::makeScaleWalkFactor(size_t k) const {
  const double q = std::max(aiding_.odometer.scale_random_walk_per_sqrt_s,
                            options_.min_odometer_scale_random_walk_per_sqrt_s);
  return new OdometerScaleWalkFactor(q, node(k + 1).t_s - node(k).t_s);
}

OdometerScalePriorFactor* FgoGraph::makeScalePrior() const {
  return new OdometerScalePriorFactor(0.0, aiding_.odometer.scale_std);
}

BiasFactor* FgoGraph::makeImuScaleFactor(size_t k) const {
  return new BiasFactor(gyro_scale_process_, accel_scale_process_, node(k + 1).t_s - node(k).t_s);
}

ImuScalePriorFactor* FgoGraph::makeImuScalePrior() const {
  // The EKF's initial scale sigmas: the profile's steady-state ones.
  return new ImuScalePriorFactor(gyro_scale_process_.sigma, accel_scale_process_.sigma);
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
  const double sbg =
      std::max(prof.gyro_bias_initial_std_rad_s > 0 ? prof.gyro_bias_initial_std_rad_s
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
  NodeBlocks& b = const_cast<NodeBlocks&>(blocks(k));
  problem->AddParameterBlock(b.p, 3);
  problem->AddParameterBlock(b.q, 4, quaternionManifold());
  problem->AddParameterBlock(b.v, 3);
  problem->AddParameterBlock(b.bg, 3);
  problem->AddParameterBlock(b.ba, 3);
  if (imu_scale_) {
    problem->AddParameterBlock(b.sg, 3);
    problem->AddParameterBlock(b.sa, 3);
  }
  if (estimatesOdometerScale()) problem->AddParameterBlock(b.s, 1);
}

std::vector<double*> FgoGraph::preintegrationBlocks(size_t k) {
  NodeBlocks& i = blocks(k);
  NodeBlocks& j = blocks(k + 1);
  if (imu_scale_) return {i.p, i.q, i.v, i.bg, i.ba, j.p, j.q, j.v, i.sg, i.sa};
  return {i.p, i.q, i.v, i.bg, i.ba, j.p, j.q, j.v};
}

std::vector<double*> FgoGraph::biasBlocks(size_t k) {
  NodeBlocks& i = blocks(k);
  NodeBlocks& j = blocks(k + 1);
  return {i.bg, i.ba, j.bg, j.ba};
}

std::vector<double*> FgoGraph::poseBlocks(size_t k) {
  NodeBlocks& b = blocks(k);
  return {b.p, b.q, b.v};
}

std::vector<double*> FgoGraph::nodeBlocks(size_t k) {
  NodeBlocks& b = blocks(k);
  return {b.p, b.q, b.v, b.bg, b.ba};
}

std::vector<double*> FgoGraph::allBlocks(size_t k) {
  std::vector<double*> out = nodeBlocks(k);
  if (imu_scale_) {
    out.push_back(blocks(k).sg);
    out.push_back(blocks(k).sa);
  }
  if (estimatesOdometerScale()) out.push_back(blocks(k).s);
  return out;
}

std::vector<double*> FgoGraph::vehicleBlocks(size_t k, const VehicleVelocityFactor& f) {
  NodeBlocks& b = blocks(k);
  std::vector<double*> out{b.q, b.v, b.bg};
  if (f.usesScale()) out.push_back(b.s);
  return out;
}

std::vector<double*> FgoGraph::scaleWalkBlocks(size_t k) { return {blocks(k).s, blocks(k + 1).s}; }

std::vector<double*> FgoGraph::imuScaleBlocks(size_t k) {
  NodeBlocks& i = blocks(k);
  NodeBlocks& j = blocks(k + 1);
  return {i.sg, i.sa, j.sg, j.sa};
}

double FgoGraph::gnssChi2(size_t fix, size_t node) {
  std::unique_ptr<GnssPositionFactor> f(makeGnssFactor(fix));
  const std::vector<double*> blocks = poseBlocks(node);
  Eigen::Vector3d r;
  f->Evaluate(blocks.data(), r.data(), nullptr);
  return r.squaredNorm();
}

void FgoGraph::requireFinite(size_t begin, size_t end, const std::string& stage) const {
  end = std::min(end, nodeCount());
  for (size_t k = std::max(begin, layout_.nodes_base); k < end; ++k) {
    const NodeBlocks& b = blocks(k);
    const char* bad = nullptr;
    auto finite = [](const double* x, int n) {
      for (int i = 0; i < n; ++i) {
        if (!std::isfinite(x[i])) return false;
      }
      return true;
    };
    if (!finite(b.p, 3))
      bad = "position";
    else if (!finite(b.q, 4))
      bad = "attitude";
    else if (!finite(b.v, 3))
      bad = "velocity";
    else if (!finite(b.bg, 3))
      bad = "gyro bias";
    else if (!finite(b.ba, 3))
      bad = "accel bias";
    if (bad == nullptr) continue;
    std::string msg = stage + ": node " + std::to_string(k) +
                      " at t=" + std::to_string(node(k).t_s) + " has a non-finite " + bad;
    if (k > 0 && hasPreintegration(k - 1)) {
      msg += " (preintegration from node " + std::to_string(k - 1) +
             " at t=" + std::to_string(node(k - 1).t_s) + " over " +
             std::to_string(pre(k - 1)->dt_s()) + " s, " + std::to_string(node(k).gnss.size()) +
             " GNSS fixes on the node)";
    }
    throw std::runtime_error(msg);
  }
}

void FgoGraph::predictNode(size_t k) {
  const NodeValue x = blocks(k - 1).value();
  std::unique_ptr<PreintegrationFactor> f(makePreintegrationFactor(k - 1));
  NodeValue y;
  if (imu_scale_) {
    f->predict(x.p_w, x.q_wb, x.v_w, x.bg, x.ba, x.imu_scale, &y.p_w, &y.q_wb, &y.v_w);
  } else {
    f->predict(x.p_w, x.q_wb, x.v_w, x.bg, x.ba, &y.p_w, &y.q_wb, &y.v_w);
  }
  y.bg = x.bg;
  y.ba = x.ba;
  y.odometer_scale = x.odometer_scale;
  y.imu_scale = x.imu_scale;
  blocks(k).set(y);
}

void FgoGraph::outputPass(const ImuPassFn& imu, const std::vector<PvaSigma>& sigma_nodes,
                          const FgoEpochFn& output, const FgoScaleFn& scale_output,
                          const std::vector<double>& scale_sigma_nodes) const {
  OutputIntegrator out(frame_, problem_.initial.gnss_week, output, scale_output);
  const size_t n = nodeCount();
  size_t next = 0, i = 0;                 // the next node to start, the sample's index
  auto startNodes = [&](size_t sample) {  // every node whose interval starts at or before it
    for (; next < n && node(next).sample_end <= sample; ++next) {
      out.node(node(next).t_s, blocks(next).value(),
               sigma_nodes.empty() ? nullptr : &sigma_nodes[next],
               scale_sigma_nodes.empty() ? std::nan("") : scale_sigma_nodes[next]);
    }
  };
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      if (i++ < firstSample()) continue;
      startNodes(i - 1);
      out.sample(s);
    }
  });
  startNodes(std::numeric_limits<size_t>::max());
  out.finish();
}

}  // namespace graftnav
