#pragma once
// A real recording for `graftnav real-sg`, read as core/navigate's real_setup.h reads it, with
// every reader repair and warning and the problem's notes printed on stderr.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/navigate/navigate_request.h"

namespace graftnav::app {

// Notes printed as they are and warnings after "warning: ", on stderr.
RunMessages printedMessages();

// Loads the case (real read policies) and prints every reader condition.
CaseInputs loadReal(const std::string& dir);

// One IMU of the case ("ref", "tested" or a file) with the profile file; prints the reader's conditions.
ImuSelection loadImuReal(const CaseInputs& c, const std::string& which, const std::string& profile);

// makeRealProblem (graftnav/navigate/real_setup.h): every estimator starts from the same state at
// the same sample. verbose: the notes and the alignment's heading are printed. The notes are
// appended to *notes when given.
EstimationProblem problemReal(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages, bool verbose,
                              std::vector<std::string>* notes = nullptr);

}  // namespace graftnav::app
