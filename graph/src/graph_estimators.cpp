#include "graftnav/graph/graph_estimators.h"

#include "graftnav/graph/fgo_solver.h"

namespace graftnav {
namespace {

// The graph's per-epoch output as a solution sink's epochs (bias estimates, no scale factors).
FgoEpochFn toSink(SolutionSink& sink) {
  return [&sink](const NavState& s, const PvaSigma* sigma, const Eigen::Vector3d& bg,
                 const Eigen::Vector3d& ba) {
    ImuErrorEstimate e;
    e.gyro_bias_rad_s = bg;
    e.accel_bias_m_s2 = ba;
    sink.add(s, sigma, e);
  };
}

// The odometer scale estimate of the epoch that follows, when vehicle aiding estimates it.
FgoScaleFn toScaleSink(SolutionSink& sink) {
  return [&sink](const OdometerScaleEstimate& k) { sink.addOdometerScale(k); };
}

}  // namespace

void addGraphEstimators(EstimatorRegistry* registry) {
  EstimatorEntry batch{"fgo", "factor-graph batch smoother (Ceres, SuiteSparse), docs/fgo.md",
                       [](const EstimationProblem& p, const EstimatorOptions& o,
                          const ProgressFn&) { return solveBatchFgo(p, o.fgo); },
                       [](const EstimationProblem& p, const ImuPassFn& imu,
                          const EstimatorOptions& o, SolutionSink& sink) {
                         return solveBatchFgo(p, imu, o.fgo, nullptr, toSink(sink),
                                              toScaleSink(sink));
                       }};
  batch.estimates_scale_factors = false;
  registry->add(std::move(batch));
  EstimatorEntry window{
      "fgo-window", "factor-graph sliding window with marginalization, causal output",
      [](const EstimationProblem& p, const EstimatorOptions& o, const ProgressFn&) {
        return solveWindowFgo(p, o.fgo);
      },
      [](const EstimationProblem& p, const ImuPassFn& imu, const EstimatorOptions& o,
         SolutionSink& sink) {
        return solveWindowFgo(p, imu, o.fgo, nullptr, toSink(sink), toScaleSink(sink));
      }};
  window.estimates_scale_factors = false;
  registry->add(std::move(window));
}

}  // namespace graftnav
