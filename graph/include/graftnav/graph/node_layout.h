#pragma once
// Where the nodes of a factor graph sit, found in one pass over the IMU without holding it.
//
// Nodes sit on IMU sample ends: at every GNSS epoch used (the nearest sample), and every
// nodeSpacing() where GNSS is absent (outages, gaps, after the last fix). Node 0 is the
// problem's initial state. The interval from node k to node k+1 holds the IMU samples
// [node[k].sample_end, node[k+1].sample_end), never fewer than two: a one-sample preintegration
// cannot be inverted. So fixes closer together than two samples (GNSS at a high rate, jitter,
// duplicate stamps, fixes between samples) share one node, each with its own time offset from
// it, and a first fix within a sample of the initial state goes on the second sample after it.
// No fix is dropped for being close to another.
//
// The pass holds the sample times since the last node only (a few hundred with GNSS, one outage
// at most in outages); the node list grows with the recording (~250 bytes per node with the
// graph's values) unless a sliding window forgets the nodes it has left behind.

#include <Eigen/Core>
#include <cstddef>
#include <deque>
#include <memory>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/fgo_options.h"
#include "graftnav/graph/local_frame.h"

namespace graftnav {

struct GraphNode {
  double t_s = 0.0;
  size_t sample_end = 0;     // index of the first IMU sample after the node
  std::vector<size_t> gnss;  // indices into NodeLayout::fixes, ascending
};

struct GnssObservation {
  GnssFix fix;
  Eigen::Vector3d z_w;          // fix in the local frame
  Eigen::Matrix3d sqrt_info_w;  // whitening of the fix in w
  double dt_s = 0.0;            // t_fix - t_node
};

// The nodes and fixes placed so far, indexed over the whole recording. A sliding window forgets
// those it no longer needs (forgetBefore), so what it holds does not grow with the recording.
struct NodeLayout {
  std::deque<GraphNode> nodes;        // node nodes_base + i is nodes[i]
  std::deque<GnssObservation> fixes;  // GNSS used, in time order; fix fixes_base + i is fixes[i]
  std::size_t nodes_base = 0, fixes_base = 0;
  int gnss_withheld = 0;         // fixes inside outages (final when complete)
  std::size_t first_sample = 0;  // first IMU sample after the initial state
  std::size_t sample_count = 0;  // IMU samples in the recording (when complete)
  bool complete = false;         // every node placed

  std::size_t nodeCount() const { return nodes_base + nodes.size(); }
  std::size_t fixCount() const { return fixes_base + fixes.size(); }
  // Node k / fix i; throw std::out_of_range when forgotten or not placed yet.
  const GraphNode& node(std::size_t k) const;
  const GnssObservation& fix(std::size_t i) const;
  // Forgets the nodes before k (never the newest) and the fixes on them.
  void forgetBefore(std::size_t k);
};

// Places the nodes as the samples of one pass come, into a NodeLayout: a node is placed once a
// later fix lands on a later sample (or, at finish(), at the end of the recording). It holds the
// sample times since the last node (a few hundred with GNSS, one outage at most in outages).
class NodeLayoutBuilder {
 public:
  // `problem`'s fixes are read in time order, in one pass; problem, frame, options and layout
  // must outlive the builder.
  NodeLayoutBuilder(const EstimationProblem& problem, const LocalFrame& frame,
                    const FgoOptions& options, NodeLayout* layout);
  ~NodeLayoutBuilder();
  NodeLayoutBuilder(const NodeLayoutBuilder&) = delete;
  NodeLayoutBuilder& operator=(const NodeLayoutBuilder&) = delete;
  // The next sample of the recording.
  void add(const ImuSample& s);
  // Places the last nodes; the layout is then complete. Throws std::invalid_argument for fewer
  // than 2 samples, an initial state after the last sample, or fixes out of time order.
  void finish();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// The largest interval between nodes: options.max_node_spacing_s, or with vehicle aiding the
// period of its updates when shorter (each node carries one odometer / NHC factor, so the graph
// sees the vehicle as often as the filters do).
double nodeSpacing(const EstimationProblem& problem, const FgoOptions& options);

// The layout of `problem` in one pass over `imu` (problem.imu is not read; its GNSS fixes, in
// time order, from one pass over them). Throws as NodeLayoutBuilder.
NodeLayout buildNodeLayout(const EstimationProblem& problem, const LocalFrame& frame,
                           const FgoOptions& options, const ImuPassFn& imu);

}  // namespace graftnav
