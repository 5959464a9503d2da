#include "estimators.h"

#include <stdexcept>

#include "graftnav/filters/free_inertial.h"
#include "graftnav/filters/rts_smoother.h"
#include "graftnav/graph/fgo_solver.h"

namespace graftnav::app {

const std::vector<EstimatorEntry>& estimatorTable() {
  static const std::vector<EstimatorEntry> table = {
      {"ekf", "forward closed-loop 21-state GNSS/INS EKF",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn& f) {
         return runEkf(p, c.ekf, nullptr, f);
       }},
      {"rts", "EKF + Rauch-Tung-Striebel smoother",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn& f) {
         return runRts(p, c.ekf, nullptr, nullptr, f);
       }},
      {"fgo", "factor-graph batch smoother (Ceres, SuiteSparse), docs/fgo.md",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn&) {
         return solveBatchFgo(p, c.fgo);
       }},
      {"fgo-window", "factor-graph sliding window with marginalization, causal output",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn&) {
         return solveWindowFgo(p, c.fgo);
       }},
      {"free-inertial", "mechanization from the initial state, no GNSS",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn& f) {
         return runFreeInertial(p, c.ekf.output_decimation, f);
       }},
  };
  return table;
}

std::vector<std::string> estimatorNames() {
  std::vector<std::string> names;
  for (const auto& e : estimatorTable()) names.push_back(e.name);
  return names;
}

NavSolution runEstimator(const std::string& name, const EstimationProblem& problem,
                         const RunConfig& config, const ProgressFn& progress) {
  for (const auto& e : estimatorTable()) {
    if (e.name == name) return e.run(problem, config, progress);
  }
  std::string known;
  for (const auto& n : estimatorNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown estimator '" + name + "' (known: " + known + ")");
}

}  // namespace graftnav::app
