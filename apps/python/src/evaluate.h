#pragma once
// evaluate() of the Python module: the SG evaluation of a case folder (lab calibration, K
// grafted realizations of SG#1 and SG#2, the real tested IMU, SOL_REF) with the core/sg pipeline
// and the estimator table, as `graftnav evaluate` runs it, without writing files. Runs without
// the GIL; the pipeline's navigations run on the worker pool.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/run_config.h"
#include "graftnav/sg/sg_evaluation_report.h"
#include "py_case.h"

namespace graftnav::python {

struct EvaluateRequest {
  std::string estimator = "ekf";
  std::optional<int> realizations;  // K; default: the run config's grafting.realizations
  std::uint64_t seed = 1;
  int jobs = 0;  // navigations in parallel; 0: all cores
  RunConfig rc;
};

struct EvaluateOutcome {
  SgEvaluationReport report;
  std::string evaluation_json;  // evaluation.json's content
  std::vector<std::string> warnings;
};

// Throws std::invalid_argument for a case built from arrays (no lab data), an unknown estimator
// or a bad option; std::runtime_error naming the file or key when the case cannot be evaluated.
EvaluateOutcome evaluateCase(const PyCase& c, const EvaluateRequest& request);

}  // namespace graftnav::python
