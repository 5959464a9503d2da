#pragma once
// The graph shared by the batch and sliding-window solvers: node layout (graph/node_layout.h),
// preintegrations, node values, and the factory for each factor. Solvers decide which factors
// live in their ceres::Problem; this class owns the data those factors point to. It does not
// hold the IMU: each interval is preintegrated from the samples a pass has buffered
// (ImuSampleBuffer), or from the problem's series when built from one in memory.

#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/graph/bias_factor.h"
#include "graftnav/estimation/fgo_options.h"
#include "graftnav/graph/gnss_position_factor.h"
#include "graftnav/graph/imu_preintegration.h"
#include "graftnav/graph/imu_sample_buffer.h"
#include "graftnav/graph/imu_scale_prior_factor.h"
#include "graftnav/graph/local_frame.h"
#include "graftnav/graph/node_layout.h"
#include "graftnav/graph/node_prior_factor.h"
#include "graftnav/graph/output_integrator.h"
#include "graftnav/graph/preintegration_factor.h"
#include "graftnav/graph/odometer_scale_factor.h"
#include "graftnav/graph/right_quaternion_manifold.h"
#include "graftnav/graph/vehicle_velocity_factor.h"

namespace graftnav {

// Parameter blocks of one node, laid out as Ceres wants them (q in Eigen order x, y, z, w).
struct NodeBlocks {
  double p[3];
  double q[4];
  double v[3];
  double bg[3];
  double ba[3];
  double sg[3] = {0.0, 0.0, 0.0};  // gyro and accel scale factors (parameter blocks only when
  double sa[3] = {0.0, 0.0, 0.0};  // the graph estimates them)
  double s[1] = {0.0};             // odometer scale factor (a parameter block only when estimated)
  NodeValue value() const;
  void set(const NodeValue& x);
};

// Places the nodes during the graph's first sliding-window pass (one read of the IMU) instead
// of in a pass of their own.
struct PlaceNodesDuringPass {};

class FgoGraph {
 public:
  // The problem's samples in memory (problem.imu, which must outlive the graph).
  FgoGraph(const EstimationProblem& problem, const FgoOptions& options);
  // The samples from `imu` (one pass for the layout; problem.imu is not read).
  FgoGraph(const EstimationProblem& problem, const FgoOptions& options, const ImuPassFn& imu);
  // No node yet: the first window pass feeds its samples to placeSample() and calls
  // finishPlacing() (runSlidingWindow does); problem.imu is not read.
  FgoGraph(const EstimationProblem& problem, const FgoOptions& options, PlaceNodesDuringPass);

  // Whether nodes are still being placed, the next sample of the placing pass, its end.
  bool placing() const { return builder_ != nullptr; }
  void placeSample(const ImuSample& s);
  void finishPlacing();

  const LocalFrame& frame() const { return frame_; }
  // Nodes and fixes placed so far (all of them once placing() is false), indexed over the
  // recording; node(k), fix(i) throw std::out_of_range for forgotten ones.
  size_t nodeCount() const { return layout_.nodeCount(); }
  const GraphNode& node(size_t k) const { return layout_.node(k); }
  size_t fixCount() const { return layout_.fixCount(); }
  const GnssObservation& fix(size_t i) const { return layout_.fix(i); }
  int gnssWithheld() const { return layout_.gnss_withheld; }
  size_t firstSample() const { return layout_.first_sample; }
  size_t sampleCount() const { return layout_.sample_count; }
  // First sample of interval k (node k to k+1), one past its last, and the sample before it
  // (coning memory; the first sample itself when it is the recording's first). The last node's
  // interval ends with the recording (known when placing is finished).
  size_t intervalBegin(size_t k) const { return node(k).sample_end; }
  size_t intervalEnd(size_t k) const {
    return k + 1 < nodeCount() ? node(k + 1).sample_end : layout_.sample_count;
  }
  // Forgets nodes before k (their values, preintegrations and fixes): a sliding window that no
  // longer needs them keeps its memory flat.
  void forgetBefore(size_t k);
  NodeBlocks& blocks(size_t k) { return blocks_[k - layout_.nodes_base]; }
  const NodeBlocks& blocks(size_t k) const { return blocks_[k - layout_.nodes_base]; }

  // (Re)creates the preintegration from node k to k+1 about node k's current bias, from the
  // problem's series (first constructor) or from `samples` (which must hold the interval and
  // the sample before it).
  ImuPreintegration& preintegrate(size_t k);
  ImuPreintegration& preintegrate(size_t k, const ImuSampleBuffer& samples);
  // Re-preintegrates the given intervals (ascending) in one pass over `imu`.
  void preintegrateFromPass(const ImuPassFn& imu, const std::vector<size_t>& intervals);
  // Frees preintegration k (a window no longer using it).
  void releasePreintegration(size_t k) { pre(k).reset(); }
  bool hasPreintegration(size_t k) const {
    return k >= layout_.nodes_base && k - layout_.nodes_base < pre_.size() && pre(k) != nullptr;
  }
  ImuPreintegration& preintegration(size_t k) { return *pre(k); }
  // True when node k's bias estimate is far (options) from preintegration k's linearization.
  bool biasMovedFar(size_t k) const;

  // Vehicle aiding (problem().aiding): whether it is on and whether each node carries an
  // odometer scale block. observeVehicle(k, samples) records node k's observation (the rate of
  // the sample ending at it, the odometer speed there); nodes in time order, each once, k >= 1.
  bool aidsVehicle() const { return aiding_.any(); }
  bool estimatesOdometerScale() const { return aiding_.odometer.estimatesScale(); }
  void observeVehicle(size_t k, const ImuSampleBuffer& samples);
  // Whether each node carries gyro and accelerometer scale factors (FgoOptions::imu_scale_states).
  bool estimatesImuScale() const { return imu_scale_; }

  // Factories (the caller's Problem takes ownership of the returned cost functions).
  PreintegrationFactor* makePreintegrationFactor(size_t k) const;  // uses preintegration(k)
  BiasFactor* makeBiasFactor(size_t k) const;                      // node k -> k+1
  GnssPositionFactor* makeGnssFactor(size_t fix) const;
  NodePriorFactor* makeInitialPrior() const;  // on node 0
  // Node k's odometer / NHC factor (null when it has no row); scale walk node k -> k+1; the
  // scale's prior on node 0.
  VehicleVelocityFactor* makeVehicleFactor(size_t k) const;
  OdometerScaleWalkFactor* makeScaleWalkFactor(size_t k) const;
  OdometerScalePriorFactor* makeScalePrior() const;
  // IMU scale factors: their Gauss-Markov factor node k -> k+1 (the EKF's process, blocks
  // imuScaleBlocks(k)), and their zero-mean prior on node 0 (blocks sg, then sa).
  BiasFactor* makeImuScaleFactor(size_t k) const;
  ImuScalePriorFactor* makeImuScalePrior() const;
  ceres::LossFunction* gnssLoss() const { return loss_.get(); }  // owned here; may be null
  ceres::Manifold* quaternionManifold() const { return &manifold_; }

  // Adds node k's parameter blocks (quaternion on the manifold) to `problem`.
  void addNodeBlocks(ceres::Problem* problem, size_t k) const;
  // Parameter-block pointer lists for each factor type.
  std::vector<double*> preintegrationBlocks(size_t k);
  std::vector<double*> biasBlocks(size_t k);
  std::vector<double*> poseBlocks(size_t k);  // p, q, v (GNSS)
  std::vector<double*> nodeBlocks(size_t k);  // p, q, v, bg, ba (priors)
  // nodeBlocks, then sg, sa and s when estimated: every block of node k in a problem.
  std::vector<double*> allBlocks(size_t k);
  std::vector<double*> vehicleBlocks(size_t k, const VehicleVelocityFactor& f);  // q, v, bg (s)
  std::vector<double*> scaleWalkBlocks(size_t k);                                // s_k, s_k+1
  std::vector<double*> imuScaleBlocks(size_t k);  // sg_k, sa_k, sg_k+1, sa_k+1

  // Whitened squared norm of GNSS observation `fix` at node k's current values, no loss.
  double gnssChi2(size_t fix, size_t node);

  // Throws std::runtime_error naming `stage`, the first node in [begin, end) with a non-finite
  // value (index, time, block) and, when known, its preintegration interval.
  void requireFinite(size_t begin, size_t end, const std::string& stage) const;

  // Node k predicted from node k-1's current values through preintegration k-1.
  void predictNode(size_t k);
  // Sets node 0 from the initial state.
  void initializeFirstNode();

  // IMU-rate output by strapdown from each node's current values with its biases over its
  // interval (graph/output_integrator.h), one pass over `imu`, the epochs given one at a time
  // to `output`. `sigma_nodes`, when not empty, holds each node's PvaSigma, copied to the epochs
  // it starts (else sigma is null); likewise scale_sigma_nodes for the odometer scale, whose
  // epochs go to scale_output when it is set.
  void outputPass(const ImuPassFn& imu, const std::vector<PvaSigma>& sigma_nodes,
                  const FgoEpochFn& output, const FgoScaleFn& scale_output = {},
                  const std::vector<double>& scale_sigma_nodes = {}) const;

  const EstimationProblem& problem() const { return problem_; }
  const FgoOptions& options() const { return options_; }
  // Replaces solver-side options (window sizes, strides); node layout and noise stay as built.
  void setOptions(const FgoOptions& options) { options_ = options; }

 private:
  void setUp();
  // Value, preintegration and gravity slots for the nodes placed since the last call.
  void addNodeStorage();
  // Preintegration k from `count` samples about node value x (with its scales when estimated).
  ImuPreintegration& preintegrateAt(size_t k, const NodeValue& x, const ImuSample* samples,
                                    size_t count, const ImuSample* before);
  std::unique_ptr<ImuPreintegration>& pre(size_t k) { return pre_[k - layout_.nodes_base]; }
  const std::unique_ptr<ImuPreintegration>& pre(size_t k) const {
    return pre_[k - layout_.nodes_base];
  }

  const EstimationProblem& problem_;
  FgoOptions options_;
  LocalFrame frame_;
  PreintegrationNoise noise_;
  BiasProcess gyro_process_, accel_process_;
  BiasProcess gyro_scale_process_, accel_scale_process_;
  bool imu_scale_ = false;
  NodeLayout layout_;
  std::unique_ptr<NodeLayoutBuilder> builder_;  // while placing
  const ImuSeries* memory_imu_ = nullptr;       // the first constructor's samples
  // Per node from layout_.nodes_base on (deques: the addresses Ceres holds stay valid as nodes
  // are added and forgotten).
  std::deque<NodeBlocks> blocks_;
  std::deque<std::unique_ptr<ImuPreintegration>> pre_;  // interval k (none for the last node)
  std::deque<Eigen::Vector3d> gravity_point_;           // where each factor's gravity is linearized
  std::deque<VehicleObservation> vehicle_obs_;          // with aiding: observeVehicle's
  VehicleAidingOptions aiding_;
  Eigen::Matrix3d C_vb_ = Eigen::Matrix3d::Identity();
  std::unique_ptr<OdometerInterpolator> odometer_;  // opened at the first observation
  std::unique_ptr<ceres::LossFunction> loss_;
  mutable RightQuaternionManifold manifold_;
};

}  // namespace graftnav
