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
#include "graftnav/nav/nav_source.h"

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

// The same rule without holding SOL_REF: the case's reference file read once into a spool
// (io/nav_spool.h), or the reference IMU smoothed by the streamed smoother into one. Every
// evaluation then reads it as a stream, the states bit for bit those of
// resolveReferenceSolution. `reference_imu` needs only its first and last samples (the span the
// smoothed problem is built from); `reference_pass` reads its samples. c.reference needs only the
// epochs makeProblem reads (readReferenceHead). Throws std::invalid_argument when the smoother has
// no streamed form or the run config aligns from the data (the smoother would need the samples).
struct StreamedReferenceSolution {
  NavOpenFn open;
  double rate_hz = 0.0;     // (count - 1) / span of its states
  std::string description;  // as ReferenceSolution::description
  bool smoothed = false;
  std::vector<std::string> notes;  // what makeProblem assumed for the smoothed problem
};
StreamedReferenceSolution streamReferenceSolution(
    const CaseInputs& c, const CaseReferenceFile& file, const ImuSelection& reference_imu,
    const ImuPassFn& reference_pass, const RunConfig& rc, const EstimatorRegistry& estimators,
    const ReferenceSolutionOptions& options = {});

}  // namespace graftnav
