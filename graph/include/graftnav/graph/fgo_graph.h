#pragma once
// The graph shared by the batch and sliding-window solvers: node times, GNSS assignment,
// preintegrations, node values, and the factory for each factor. Solvers decide which factors
// live in their ceres::Problem; this class owns the data those factors point to.
//
// Nodes sit on IMU sample ends: at every GNSS epoch used (the nearest sample), and every
// max_node_spacing_s where GNSS is absent (outages, gaps, after the last fix). Node 0 is the
// problem's initial state. The interval from node k to node k+1 holds the IMU samples
// [node[k].sample_end, node[k+1].sample_end).

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
#include "graftnav/graph/local_frame.h"
#include "graftnav/graph/node_prior_factor.h"
#include "graftnav/graph/preintegration_factor.h"
#include "graftnav/graph/right_quaternion_manifold.h"

namespace graftnav {

// One output epoch of a factor-graph solution: state, PVA 1-sigma (null when not computed), and
// the gyro and accelerometer bias estimates.
using FgoEpochFn = std::function<void(const NavState& state, const PvaSigma* sigma,
                                      const Eigen::Vector3d& gyro_bias_rad_s,
                                      const Eigen::Vector3d& accel_bias_m_s2)>;

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

struct GraphNode {
  double t_s = 0.0;
  size_t sample_end = 0;        // index of the first IMU sample after the node
  std::vector<size_t> gnss;     // indices into FgoGraph::fixes()
};

struct GnssObservation {
  GnssFix fix;
  Eigen::Vector3d z_w;           // fix in the local frame
  Eigen::Matrix3d sqrt_info_w;   // whitening of the fix in w
  double dt_s = 0.0;             // t_fix - t_node
};

class FgoGraph {
 public:
  FgoGraph(const EstimationProblem& problem, const FgoOptions& options);

  const LocalFrame& frame() const { return frame_; }
  const std::vector<GraphNode>& nodes() const { return nodes_; }
  const std::vector<GnssObservation>& fixes() const { return fixes_; }
  int gnssWithheld() const { return gnss_withheld_; }
  NodeBlocks& blocks(size_t k) { return blocks_[k]; }
  const NodeBlocks& blocks(size_t k) const { return blocks_[k]; }

  // (Re)creates the preintegration from node k to k+1 about node k's current bias.
  ImuPreintegration& preintegrate(size_t k);
  bool hasPreintegration(size_t k) const { return k < pre_.size() && pre_[k] != nullptr; }
  ImuPreintegration& preintegration(size_t k) { return *pre_[k]; }
  // True when node k's bias estimate is far (options) from preintegration k's linearization.
  bool biasMovedFar(size_t k) const;

  // Factories (the caller's Problem takes ownership of the returned cost functions).
  PreintegrationFactor* makePreintegrationFactor(size_t k) const;  // uses preintegration(k)
  BiasFactor* makeBiasFactor(size_t k) const;                      // node k -> k+1
  GnssPositionFactor* makeGnssFactor(size_t fix) const;
  NodePriorFactor* makeInitialPrior() const;                       // on node 0
  ceres::LossFunction* gnssLoss() const { return loss_.get(); }    // owned here; may be null
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

  // IMU-rate output by strapdown from each node's values with its biases over its interval.
  // `sigma_nodes`, when not empty, holds each node's PvaSigma, copied to the epochs it starts.
  NavSolution integrateOutput(const std::string& estimator,
                              const std::vector<PvaSigma>& sigma_nodes) const;
  // The same epochs given one at a time to `output` (nothing held): sigma is null when
  // sigma_nodes is empty.
  void integrateOutput(const std::vector<PvaSigma>& sigma_nodes, const FgoEpochFn& output) const;

  const EstimationProblem& problem() const { return problem_; }
  const FgoOptions& options() const { return options_; }
  // Replaces solver-side options (window sizes, strides); node layout and noise stay as built.
  void setOptions(const FgoOptions& options) { options_ = options; }

 private:
  void buildNodes();

  const EstimationProblem& problem_;
  FgoOptions options_;
  LocalFrame frame_;
  PreintegrationNoise noise_;
  BiasProcess gyro_process_, accel_process_;
  std::vector<GraphNode> nodes_;
  std::vector<GnssObservation> fixes_;
  std::vector<NodeBlocks> blocks_;
  std::vector<std::unique_ptr<ImuPreintegration>> pre_;
  std::vector<Eigen::Vector3d> gravity_point_;  // where each factor's gravity is linearized
  std::unique_ptr<ceres::LossFunction> loss_;
  mutable RightQuaternionManifold manifold_;
  int gnss_withheld_ = 0;
  size_t first_sample_ = 0;
};

}  // namespace graftnav
