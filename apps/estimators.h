#pragma once
// Estimators by name: one table, name -> function(problem, run config, progress) -> NavSolution.
// To add one, append an entry in estimators.cpp (e.g. "fgo", "fgo-window").

#include <functional>
#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/filters/ekf.h"
#include "run_config.h"

namespace graftnav::app {

using EstimatorFn =
    std::function<NavSolution(const EstimationProblem&, const RunConfig&, const ProgressFn&)>;

struct EstimatorEntry {
  std::string name;
  std::string description;
  EstimatorFn run;
};

const std::vector<EstimatorEntry>& estimatorTable();
std::vector<std::string> estimatorNames();
// Throws std::invalid_argument listing the known names when `name` is not in the table.
NavSolution runEstimator(const std::string& name, const EstimationProblem& problem,
                         const RunConfig& config, const ProgressFn& progress = {});

}  // namespace graftnav::app
