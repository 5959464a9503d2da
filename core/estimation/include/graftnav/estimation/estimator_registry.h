#pragma once
// Estimators by name: the table every command, batch task and the Python module picks an
// estimator from. The registry is a plain value type here, in core, so that code that runs an
// estimator on a case (core/case, core/sg, core/mismatch) takes it as an argument without
// depending on filters/ or graph/. filters/ and graph/ each add their own estimators
// (filters/filter_estimators.h, graph/graph_estimators.h); the full table is assembled above
// them (apps/estimators: graftnav/estimators/estimator_table.h).
#include <functional>
#include <string>
#include <vector>

#include "graftnav/estimation/ekf_options.h"
#include "graftnav/estimation/fgo_options.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/solution_sink.h"

namespace graftnav {

// The options every estimator may read: each takes its own section (the run config's ekf: and
// fgo: sections, core/case/run_config.h).
struct EstimatorOptions {
  EkfOptions ekf;
  FgoOptions fgo;
};

// In memory: the problem's samples (problem.imu), the solution returned whole.
using EstimatorFn = std::function<NavSolution(const EstimationProblem&, const EstimatorOptions&,
                                              const ProgressFn&)>;
// Streamed: the samples from `imu` (problem.imu is not read), the output epochs into `sink`, the
// GNSS bookkeeping returned (no states). Same epochs as the in-memory form; memory does not grow
// with the recording (docs/BENCHMARKS.md).
using StreamingEstimatorFn = std::function<NavSolution(
    const EstimationProblem&, const ImuPassFn& imu, const EstimatorOptions&, SolutionSink& sink)>;

struct EstimatorEntry {
  std::string name;
  std::string description;
  EstimatorFn run;
  StreamingEstimatorFn stream;  // empty when the estimator holds its input in memory
  // Whether the solution has scale-factor series (imu_errors.txt is written only then).
  bool estimates_scale_factors = true;
  // When set, decides that per run instead (an estimator whose scale states are an option).
  std::function<bool(const EstimationProblem&, const EstimatorOptions&)>
      estimates_scale_factors_when{};
  bool estimatesScaleFactors(const EstimationProblem& p, const EstimatorOptions& o) const {
    return estimates_scale_factors_when ? estimates_scale_factors_when(p, o)
                                        : estimates_scale_factors;
  }
  // Whether the estimator takes GNSS (false: a free-inertial run, no GNSS read or expected).
  bool uses_gnss = true;
  // The forward filter this estimator smooths, when it is one (rts: "ekf"); empty otherwise. The
  // difference of the two solutions then has the variance P_filter - P_smoother (cross-check).
  std::string smooths{};
};

class EstimatorRegistry {
 public:
  // Throws std::invalid_argument when the name is empty or already taken, or `run` is empty.
  void add(EstimatorEntry entry);

  const std::vector<EstimatorEntry>& entries() const { return entries_; }
  std::vector<std::string> names() const;
  bool contains(const std::string& name) const;
  // Throws std::invalid_argument "unknown estimator 'x' (known: a, b, ...)".
  const EstimatorEntry& find(const std::string& name) const;
  // "a, b, c": the names for messages and --help.
  std::string namesText() const;

  NavSolution run(const std::string& name, const EstimationProblem& problem,
                  const EstimatorOptions& options, const ProgressFn& progress = {}) const;
  // Whether `name` has a streamed form; throws like find() for an unknown name.
  bool canStream(const std::string& name) const;
  // Throws std::invalid_argument when `name` has no streamed form.
  NavSolution runStreaming(const std::string& name, const EstimationProblem& problem,
                           const ImuPassFn& imu, const EstimatorOptions& options,
                           SolutionSink& sink) const;

 private:
  std::vector<EstimatorEntry> entries_;
};

}  // namespace graftnav
