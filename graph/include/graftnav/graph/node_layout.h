#pragma once
// Where the nodes of a factor graph sit, found in one pass over the IMU without holding it.
//
// Nodes sit on IMU sample ends: at every GNSS epoch used (the nearest sample), and every
// max_node_spacing_s where GNSS is absent (outages, gaps, after the last fix). Node 0 is the
// problem's initial state. The interval from node k to node k+1 holds the IMU samples
// [node[k].sample_end, node[k+1].sample_end).
//
// The pass holds the sample times since the last node only (a few hundred with GNSS, one outage
// at most in outages): memory grows with the recording by the node list alone (~100 bytes per
// node).

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/graph/fgo_options.h"
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

struct NodeLayout {
  std::vector<GraphNode> nodes;
  std::vector<GnssObservation> fixes;  // GNSS used, in time order
  int gnss_withheld = 0;               // fixes inside outages
  size_t first_sample = 0;             // first IMU sample after the initial state
  size_t sample_count = 0;             // IMU samples in the recording
};

// The layout of `problem` (its IMU samples come from `imu`, problem.imu is not read; its GNSS
// fixes, in time order, from one pass over them). Throws std::invalid_argument for fewer than 2
// samples, an initial state after the last sample, or fixes out of time order.
NodeLayout buildNodeLayout(const EstimationProblem& problem, const LocalFrame& frame,
                           const FgoOptions& options, const ImuPassFn& imu);

}  // namespace graftnav
