#pragma once
// Sliding-window pass over an FgoGraph: adds nodes in time order, solves a window of the last
// options.window_nodes nodes, and marginalizes the oldest into a linear prior on the next
// (Schur complement of the Gauss-Newton system of the factors touching it; docs/fgo.md, 4).
// Used as the "fgo-window" estimator and as the initializer of the batch smoother.

#include <vector>

#include "graftnav/graph/fgo_graph.h"
#include "graftnav/graph/fgo_solver.h"

namespace graftnav {

struct WindowResult {
  std::vector<NodeValue> causal;  // each node when it entered the window (after that solve)
  std::vector<NodeValue> lagged;  // each node when it left the window (or at the end)
};

// Runs the window over all nodes of `graph`. Afterwards graph.blocks(k) hold the lagged values,
// and every preintegration exists. Counts go to `report` when given.
WindowResult runSlidingWindow(FgoGraph& graph, FgoReport* report);

// Linear prior on node m+1 from marginalizing node m out of the given residual blocks
// (exposed for tests): H, b of the factors over [node m, node m+1] tangent (30 dims), Schur
// complement on node m+1, factored as NodePriorFactor(x_{m+1}, S, e).
NodePriorFactor* marginalizeNode(FgoGraph& graph, ceres::Problem& problem, size_t m,
                                 const std::vector<ceres::ResidualBlockId>& residuals);

}  // namespace graftnav
