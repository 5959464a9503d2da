#include "graftnav/case/reference_solution.h"

#include <stdexcept>

#include "graftnav/case/problem.h"

namespace graftnav {

ReferenceSolution resolveReferenceSolution(const CaseInputs& c, const ReferenceImuFn& reference_imu,
                                           const RunConfig& rc, const EstimatorRegistry& estimators,
                                           const ReferenceSolutionOptions& o) {
  ReferenceSolution r;
  if (o.use_case_reference && !c.reference.empty()) {
    r.states = c.reference;
    r.description = c.reference_is_truth ? "truth (" + c.reference_name + ")"
                                         : "external reference solution (" + c.reference_name + ")";
    return r;
  }
  const ImuSelection ref = reference_imu();
  if (!ref.profile_given)
    throw std::runtime_error(
        c.paths().caseYaml() + ": reference_imu needs noise parameters to smooth SOL_REF" +
        (c.reference.empty() ? " (the case has no truth or reference solution)" : ""));
  EstimationProblem pr = makeProblem(c, ref, rc, std::nullopt, &r.notes);
  if (o.start_at_initial_state) startAtInitialState(&pr, &r.notes);
  r.states = estimators.run(o.smoother, pr, rc).states;
  r.description = "RTS-smoothed reference IMU with all GNSS (SOL_REF of the seed)";
  r.smoothed = true;
  return r;
}

}  // namespace graftnav
