#pragma once
// IMU-rate output of a factor graph: strapdown from each node's optimized value with its biases
// (and IMU scale factors, zero when not estimated) over the node's interval, one epoch at a time. Each epoch is held back by one: a node's own
// epoch, already integrated as the end of the previous interval, is replaced by the node
// estimate so that the solution passes exactly through the optimized nodes.

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>

#include "graftnav/estimation/imu_error_estimate.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/graph/local_frame.h"
#include "graftnav/graph/node_prior_factor.h"
#include "graftnav/nav/mechanization.h"

namespace graftnav {

// One output epoch of a factor-graph solution: state, PVA 1-sigma (null when not computed), and
// the IMU error estimates (biases; scale factors, zero when the graph has none).
using FgoEpochFn = std::function<void(const NavState& state, const PvaSigma* sigma,
                                      const ImuErrorEstimate& sensors)>;

// With an odometer scale estimated: its value (and 1-sigma, NaN when not computed) at the epoch
// given next, called just before the FgoEpochFn of that epoch.
using FgoScaleFn = std::function<void(const OdometerScaleEstimate& estimate)>;

class OutputIntegrator {
 public:
  // scale_output (may be empty) receives each epoch's odometer scale: x.odometer_scale of the
  // node starting its interval.
  OutputIntegrator(const LocalFrame& frame, int gnss_week, FgoEpochFn output,
                   FgoScaleFn scale_output = {});
  // Starts the next node's interval (nodes in time order) at its value `x` at t_s; `sigma`
  // (null: none) and the scale's 1-sigma go with every epoch the interval gives.
  void node(double t_s, const NodeValue& x, const PvaSigma* sigma,
            double scale_std = std::numeric_limits<double>::quiet_NaN());
  // The next raw sample of the current interval.
  void sample(const ImuSample& raw);
  // Gives the last epoch.
  void finish();

 private:
  struct Epoch {
    NavState state;
    ImuErrorEstimate sensors;
    PvaSigma sigma;
    bool has_sigma = false;
    OdometerScaleEstimate scale;
  };
  void emit() {
    if (scale_output_) scale_output_(pending_.scale);
    output_(pending_.state, pending_.has_sigma ? &pending_.sigma : nullptr, pending_.sensors);
  }

  const LocalFrame& frame_;
  int gnss_week_;
  FgoEpochFn output_;
  FgoScaleFn scale_output_;
  std::optional<Strapdown> sd_;
  NodeValue x_;    // the current node
  Epoch pending_;  // the epoch held back
};

}  // namespace graftnav
