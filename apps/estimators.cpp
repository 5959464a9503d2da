#include "estimators.h"

#include <stdexcept>

#include "graftnav/filters/free_inertial.h"
#include "graftnav/filters/rts_smoother.h"

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
