#pragma once
// Loading a real recording for `graftnav real` and `real-sg`: the lenient read policies, every
// reader repair and warning printed, and the estimator inputs started at the initial state's epoch.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/problem.h"
#include "graftnav/case/run_config.h"

namespace graftnav::app {

// Prints each line of `text` to stderr after `prefix`.
void printLines(const std::string& prefix, const std::string& text);

// Loads the case (real read policies) and prints every reader condition.
CaseInputs loadReal(const std::string& dir);

// One IMU of the case ("ref", "tested" or a file) with the profile file; prints the reader's conditions.
ImuSelection loadImuReal(const CaseInputs& c, const std::string& which, const std::string& profile);

// makeProblem, then startAtInitialState (graftnav/case/problem.h): every estimator starts from
// the same state at the same sample. verbose: the notes and the alignment's heading are printed.
// The notes are appended to *notes when given.
EstimationProblem problemReal(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages, bool verbose,
                              std::vector<std::string>* notes = nullptr);

}  // namespace graftnav::app
