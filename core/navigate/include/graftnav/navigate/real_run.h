#pragma once
// The estimators of `graftnav real` on a recording read by loadRealInputs (real_setup.h). Per
// estimator: out_dir/<name>/solution.nav, the errors at the check points (checkpoints.csv) and
// the errors against the reference solution. Streamed inputs: the IMU read in blocks, every epoch
// written, evaluated against the reference (read as a stream, StreamedEvaluation) and at the check
// points (StreamedCheckpoints) as it comes, no solution held. Otherwise the solution is held and
// evaluated whole. The files and numbers are the same either way.
#include <string>
#include <vector>

#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/eval/real_report.h"
#include "graftnav/navigate/navigate_request.h"
#include "graftnav/navigate/real_setup.h"

namespace graftnav {

// Runs each of `estimators` in turn. A failure (an unknown name, an estimator's error, a
// non-finite state) is given as a warning and listed in *failed ("name: why"); its folder is not
// written and the others go on. A failed evaluation against the reference is a warning and leaves
// EstimatorRun::ref empty.
std::vector<EstimatorRun> runRealEstimators(const RealInputs& inputs,
                                            const std::vector<std::string>& estimators,
                                            const EstimatorRegistry& registry,
                                            const std::string& out_dir, const RunMessages& messages,
                                            std::vector<std::string>* failed);

}  // namespace graftnav
