#pragma once
// Sliding-window pass over an FgoGraph: adds nodes in time order, solves a window of the last
// options.window_nodes nodes, and marginalizes the oldest into a linear prior on the next
// (Schur complement of the Gauss-Newton system of the factors touching it; docs/fgo.md, 4).
// Used as the "fgo-window" estimator and as the initializer of the batch smoother.
//
// The samples come from one pass over the IMU; the pass holds those of the window's intervals
// only (ImuSampleBuffer) and the graph forgets the nodes behind the window, so memory does not
// grow with the recording.

#include <deque>
#include <vector>

#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/fgo_solver.h"
#include "graftnav/graph/imu_sample_buffer.h"

namespace graftnav {

// What a window pass hands out. `samples` holds at least the intervals of the nodes in the
// window (and, in entered(k), samples up to node k's).
class WindowListener {
 public:
  virtual ~WindowListener() = default;
  // Node k as estimated when it entered the window (after that solve); node 0 at the start.
  virtual void entered(size_t /*k*/, const NodeValue& /*x*/, const ImuSampleBuffer& /*samples*/) {}
  // Node k when it left the window (marginalized), or at the end of the pass.
  virtual void left(size_t /*k*/, const NodeValue& /*x*/, const ImuSampleBuffer& /*samples*/) {}
  // After the last node's left().
  virtual void finished(const ImuSampleBuffer& /*samples*/) {}
};

// Runs the window over all nodes of `graph` with the samples of one pass over `imu`; when the
// graph is still placing its nodes (PlaceNodesDuringPass), the pass places them as it goes.
// keep_preintegrations: every interval's preintegration and node stays in the graph (the batch
// re-uses them; afterwards graph.blocks(k) hold the lagged values); otherwise each node is
// forgotten (FgoGraph::forgetBefore) once it has left the window and its output is given, so
// the graph holds the window's nodes only. Counts go to `report` when given.
void runSlidingWindow(FgoGraph& graph, const ImuPassFn& imu, FgoReport* report,
                      bool keep_preintegrations, WindowListener* listener = nullptr);

// Linear prior on node m+1 from marginalizing node m out of the given residual blocks
// (exposed for tests): H, b of the factors over [node m, node m+1] tangent (30 dims; 32 with
// the odometer scale), Schur complement on node m+1, factored as NodePriorFactor(x_{m+1}, S, e)
// (NodeScalePriorFactor with the scale), over graph.allBlocks(m + 1).
ceres::CostFunction* marginalizeNode(FgoGraph& graph, ceres::Problem& problem, size_t m,
                                     const std::vector<ceres::ResidualBlockId>& residuals);

}  // namespace graftnav
