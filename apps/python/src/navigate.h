#pragma once
// navigate() of the Python module: one estimator on one IMU of a case, in memory, and its errors
// against the case's truth or reference solution, the way `graftnav navigate` runs them (the
// same run config, checks, problem and evaluation, so the statistics equal errors.json's).
// Runs without the GIL: it touches no Python object.
#include <string>
#include <vector>

#include "graftnav/case/run_config.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/evaluation.h"
#include "py_case.h"

namespace graftnav::python {

struct NavigateRequest {
  std::string estimator = "ekf";
  std::string imu;  // "ref" | "tested"
  RunConfig rc;
};

struct NavigateOutcome {
  NavSolution solution;
  std::vector<TimeWindow> outages;
  bool evaluated = false;       // the case has a truth or reference solution
  std::string statistics_json;  // errors.json's content when evaluated
  std::string reference;        // what the errors are against
  std::vector<std::string> notes, warnings;
};

// Throws std::invalid_argument for an unknown estimator, std::runtime_error naming the input
// when the case cannot be navigated (the CLI's checks).
NavigateOutcome navigateCase(const PyCase& c, const NavigateRequest& request);

}  // namespace graftnav::python
