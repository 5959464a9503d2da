#pragma once
// IMU-rate output of a factor graph: strapdown from each node's optimized value with its biases
// over the node's interval, one epoch at a time. Each epoch is held back by one: a node's own
// epoch, already integrated as the end of the previous interval, is replaced by the node
// estimate so that the solution passes exactly through the optimized nodes.

#include <Eigen/Core>
#include <functional>
#include <optional>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/graph/local_frame.h"
#include "graftnav/graph/node_prior_factor.h"
#include "graftnav/nav/mechanization.h"

namespace graftnav {

// One output epoch of a factor-graph solution: state, PVA 1-sigma (null when not computed), and
// the gyro and accelerometer bias estimates.
using FgoEpochFn = std::function<void(const NavState& state, const PvaSigma* sigma,
                                      const Eigen::Vector3d& gyro_bias_rad_s,
                                      const Eigen::Vector3d& accel_bias_m_s2)>;

class OutputIntegrator {
 public:
  OutputIntegrator(const LocalFrame& frame, int gnss_week, FgoEpochFn output);
  // Starts the next node's interval (nodes in time order) at its value `x` at t_s; `sigma`
  // (null: none) goes with every epoch the interval gives.
  void node(double t_s, const NodeValue& x, const PvaSigma* sigma);
  // The next raw sample of the current interval.
  void sample(const ImuSample& raw);
  // Gives the last epoch.
  void finish();

 private:
  struct Epoch {
    NavState state;
    Eigen::Vector3d bg, ba;
    PvaSigma sigma;
    bool has_sigma = false;
  };
  void emit() {
    output_(pending_.state, pending_.has_sigma ? &pending_.sigma : nullptr, pending_.bg,
            pending_.ba);
  }

  const LocalFrame& frame_;
  int gnss_week_;
  FgoEpochFn output_;
  std::optional<Strapdown> sd_;
  NodeValue x_;    // the current node
  Epoch pending_;  // the epoch held back
};

}  // namespace graftnav
