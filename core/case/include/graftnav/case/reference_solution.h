#pragma once
// SOL_REF, the solution a run's errors are measured against: the case's truth (field/truth.nav)
// or reference solution when it has one, else the reference IMU smoothed (RTS) with all GNSS,
// as the seed defines it. One rule for evaluate, real-sg, diagnose and the batch.
#include <functional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"

namespace graftnav {

struct ReferenceSolutionOptions {
  // The case's truth or reference solution when it has one; false: always smooth (evaluate
  // --sol-ref smooth; real-sg, whose reference.nav comes from another system).
  bool use_case_reference = true;
  // The smoothed problem starts at the initial state's epoch (startAtInitialState), as every
  // estimator of a real recording does.
  bool start_at_initial_state = false;
  std::string smoother = "rts";
};

struct ReferenceSolution {
  NavSeries states;
  std::string description;         // what it is, for reports ("truth (path)", ...)
  bool smoothed = false;           // made here from the reference IMU
  std::vector<std::string> notes;  // what makeProblem assumed for the smoothed problem
};

// The reference IMU, loaded only when it is smoothed.
using ReferenceImuFn = std::function<ImuSelection()>;

// Throws std::runtime_error naming case.yaml when the reference IMU must be smoothed but has no
// noise parameters.
ReferenceSolution resolveReferenceSolution(const CaseInputs& c, const ReferenceImuFn& reference_imu,
                                           const RunConfig& rc, const EstimatorRegistry& estimators,
                                           const ReferenceSolutionOptions& options = {});

}  // namespace graftnav
