#pragma once
// The graph shared by the batch and sliding-window solvers: node layout (graph/node_layout.h),
// preintegrations, node values, and the factory for each factor. Solvers decide which factors
// live in their ceres::Problem; this class owns the data those factors point to. It does not
// hold the IMU: each interval is preintegrated from the samples a pass has buffered
// (ImuSampleBuffer), or from the problem's series when built from one in memory.

#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <functional>
#include <memory>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/graph/bias_factor.h"
#include "graftnav/graph/fgo_options.h"
#include "graftnav/graph/gnss_position_factor.h"
#include "graftnav/graph/imu_preintegration.h"
#include "graftnav/graph/imu_sample_buffer.h"
#include "graftnav/graph/local_frame.h"
#include "graftnav/graph/node_layout.h"
#include "graftnav/graph/node_prior_factor.h"
#include "graftnav/graph/output_integrator.h"
#include "graftnav/graph/preintegration_factor.h"
#include "graftnav/graph/right_quaternion_manifold.h"

namespace graftnav {

// Parameter blocks of one node, laid out as Ceres wants them (q in Eigen order x, y, z, w).
struct NodeBlocks {
  double p[3];
  double q[4];
  double v[3];
  double bg[3];
  double ba[3];
  NodeValue value() const;
  void set(const NodeValue& x);
};

class FgoGraph {
 public:
  // The problem's samples in memory (problem.imu, which must outlive the graph).
  FgoGraph(const EstimationProblem& problem, const FgoOptions& options);
  // The samples from `imu` (one pass for the layout; problem.imu is not read).
  FgoGraph(const EstimationProblem& problem, const FgoOptions& options, const ImuPassFn& imu);

  const LocalFrame& frame() const { return frame_; }
  const std::vector<GraphNode>& nodes() const { return layout_.nodes; }
  const std::vector<GnssObservation>& fixes() const { return layout_.fixes; }
  int gnssWithheld() const { return layout_.gnss_withheld; }
  size_t firstSample() const { return layout_.first_sample; }
  size_t sampleCount() const { return layout_.sample_count; }
  // First sample of interval k (node k to k+1), one past its last, and the sample before it
  // (coning memory; the first sample itself when it is the recording's first).
  size_t intervalBegin(size_t k) const { return layout_.nodes[k].sample_end; }
  size_t intervalEnd(size_t k) const {
    return k + 1 < layout_.nodes.size() ? layout_.nodes[k + 1].sample_end : layout_.sample_count;
  }
  NodeBlocks& blocks(size_t k) { return blocks_[k]; }
  const NodeBlocks& blocks(size_t k) const { return blocks_[k]; }

  // (Re)creates the preintegration from node k to k+1 about node k's current bias, from the
  // problem's series (first constructor) or from `samples` (which must hold the interval and
  // the sample before it).
  ImuPreintegration& preintegrate(size_t k);
  ImuPreintegration& preintegrate(size_t k, const ImuSampleBuffer& samples);
  // Re-preintegrates the given intervals (ascending) in one pass over `imu`.
  void preintegrateFromPass(const ImuPassFn& imu, const std::vector<size_t>& intervals);
  // Frees preintegration k (a window no longer using it).
  void releasePreintegration(size_t k) { pre_[k].reset(); }
  bool hasPreintegration(size_t k) const { return k < pre_.size() && pre_[k] != nullptr; }
  ImuPreintegration& preintegration(size_t k) { return *pre_[k]; }
  // True when node k's bias estimate is far (options) from preintegration k's linearization.
  bool biasMovedFar(size_t k) const;

  // Factories (the caller's Problem takes ownership of the returned cost functions).
  PreintegrationFactor* makePreintegrationFactor(size_t k) const;  // uses preintegration(k)
  BiasFactor* makeBiasFactor(size_t k) const;                      // node k -> k+1
  GnssPositionFactor* makeGnssFactor(size_t fix) const;
  NodePriorFactor* makeInitialPrior() const;                     // on node 0
  ceres::LossFunction* gnssLoss() const { return loss_.get(); }  // owned here; may be null
  ceres::Manifold* quaternionManifold() const { return &manifold_; }

  // Adds node k's parameter blocks (quaternion on the manifold) to `problem`.
  void addNodeBlocks(ceres::Problem* problem, size_t k) const;
  // Parameter-block pointer lists for each factor type.
  std::vector<double*> preintegrationBlocks(size_t k);
  std::vector<double*> biasBlocks(size_t k);
  std::vector<double*> poseBlocks(size_t k);  // p, q, v (GNSS)
  std::vector<double*> nodeBlocks(size_t k);  // p, q, v, bg, ba (priors)

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
  // it starts (else sigma is null).
  void outputPass(const ImuPassFn& imu, const std::vector<PvaSigma>& sigma_nodes,
                  const FgoEpochFn& output) const;

  const EstimationProblem& problem() const { return problem_; }
  const FgoOptions& options() const { return options_; }
  // Replaces solver-side options (window sizes, strides); node layout and noise stay as built.
  void setOptions(const FgoOptions& options) { options_ = options; }

 private:
  void setUp(const ImuPassFn& imu);

  const EstimationProblem& problem_;
  FgoOptions options_;
  LocalFrame frame_;
  PreintegrationNoise noise_;
  BiasProcess gyro_process_, accel_process_;
  NodeLayout layout_;
  const ImuSeries* memory_imu_ = nullptr;  // the first constructor's samples
  std::vector<NodeBlocks> blocks_;
  std::vector<std::unique_ptr<ImuPreintegration>> pre_;
  std::vector<Eigen::Vector3d> gravity_point_;  // where each factor's gravity is linearized
  std::unique_ptr<ceres::LossFunction> loss_;
  mutable RightQuaternionManifold manifold_;
};

}  // namespace graftnav
