#pragma once
// Factor-graph estimators: batch smoother over the whole data set ("fgo") and sliding window
// with marginalization ("fgo-window"). Both return the common NavSolution at the IMU rate, made
// by strapdown integration from the optimized nodes with their biases. docs/fgo.md.

#include <limits>
#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/graph/fgo_graph.h"
#include "graftnav/estimation/fgo_options.h"

namespace graftnav {

// What a solve did (for reports, benchmarks and tests). All times wall-clock seconds.
struct FgoReport {
  int nodes = 0;
  int gnss_factors = 0;
  int gnss_culled = 0;                 // removed by the chi-square test after a solve
  std::vector<double> culled_times_s;  // their epochs
  std::vector<double> culled_chi2;     // and their whitened squared residuals
  int cull_refused = 0;                // batch: fixes that failed when too many failed to cull any
  int reintegrations = 0;              // preintegrations redone because the bias moved far
  int vehicle_factors = 0;             // odometer / NHC factors (vehicle aiding)
  int solves = 0;
  int iterations = 0;          // total solver iterations
  double initial_cost = 0.0;   // batch: first solve's initial cost
  double final_cost = 0.0;     // batch: last solve's final cost
  double window_time_s = 0.0;  // sliding window pass (the batch's initializer; fgo-window: with
                               // its output, written as the window goes)
  double batch_time_s = 0.0;   // batch solves (not counting the window pass)
  double covariance_time_s = 0.0;
  // Batch with compute_covariance and IMU scale states: the last node's gyro then accelerometer
  // scale-factor 1-sigmas (fraction; NaN otherwise).
  Eigen::Matrix<double, 6, 1> imu_scale_std_last =
      Eigen::Matrix<double, 6, 1>::Constant(std::numeric_limits<double>::quiet_NaN());
  double output_time_s = 0.0;  // batch: IMU-rate integration of the output
  std::string summary;         // one-line text summary
};

// Batch: initializes the nodes with a sliding-window (fixed-lag) pass, then solves the full
// graph with Levenberg-Marquardt on SPARSE_NORMAL_CHOLESKY (SuiteSparse), culls GNSS outliers by
// chi-square and re-solves, re-preintegrates intervals whose bias moved far and re-solves.
// With `output`, the IMU-rate epochs go there one at a time instead of into the returned
// solution (which then holds only the GNSS bookkeeping), and, with vehicle aiding that
// estimates the odometer scale, each epoch's scale to `scale_output` first.
NavSolution solveBatchFgo(const EstimationProblem& problem, const FgoOptions& options,
                          FgoReport* report = nullptr, const FgoEpochFn& output = {},
                          const FgoScaleFn& scale_output = {});
// The same with the samples from passes over `imu` (problem.imu is not read): the graph holds
// one preintegration per node, not the samples. Passes: the window initialization (which places
// the nodes), one per re-preintegration round that has work, and the output.
NavSolution solveBatchFgo(const EstimationProblem& problem, const ImuPassFn& imu,
                          const FgoOptions& options, FgoReport* report = nullptr,
                          const FgoEpochFn& output = {}, const FgoScaleFn& scale_output = {});

// Sliding window of options.window_nodes nodes; the oldest node is marginalized into a
// Schur-complement prior on the next. Output is causal (each node as estimated when it entered
// the window) unless options.window_fixed_lag_output.
NavSolution solveWindowFgo(const EstimationProblem& problem, const FgoOptions& options,
                           FgoReport* report = nullptr, const FgoEpochFn& output = {},
                           const FgoScaleFn& scale_output = {});
// The same with the samples from one pass over `imu` (problem.imu is not read): the nodes are
// placed as the samples come and the window writes its output as it goes, holding the window's
// samples and nodes (in an outage, those since the last node: the nodes inside it are placed
// when GNSS returns).
NavSolution solveWindowFgo(const EstimationProblem& problem, const ImuPassFn& imu,
                           const FgoOptions& options, FgoReport* report = nullptr,
                           const FgoEpochFn& output = {}, const FgoScaleFn& scale_output = {});

// One pass over a series held in memory (the whole series as one block); `imu` must outlive it.
ImuPassFn seriesPass(const ImuSeries& imu);

}  // namespace graftnav
