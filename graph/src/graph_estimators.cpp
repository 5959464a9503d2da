#include "graftnav/graph/graph_estimators.h"

#include "graftnav/graph/fgo_solver.h"

namespace graftnav {
namespace {

// The graph's per-epoch output as a solution sink's epochs.
FgoEpochFn toSink(SolutionSink& sink) {
  return [&sink](const NavState& s, const PvaSigma* sigma, const ImuErrorEstimate& e) {
    sink.add(s, sigma, e);
  };
}

// Whether a run has IMU scale-factor series (FgoGraph::estimatesImuScale's rule).
bool graphEstimatesImuScale(const EstimationProblem& p, const EstimatorOptions& o) {
  const ImuScaleStates mode = o.fgo.imu_scale_states;
  return mode == ImuScaleStates::kOn ||
         (mode == ImuScaleStates::kWithVehicleAiding && p.aiding.any());
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
  batch.estimates_scale_factors_when = graphEstimatesImuScale;
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
  window.estimates_scale_factors_when = graphEstimatesImuScale;
  registry->add(std::move(window));
}

}  // namespace graftnav
