#pragma once
// The estimator inputs (EstimationProblem) of a case for one IMU series: initial state,
// alignment, lever arm, GNSS selection and outages.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/nav_solution.h"

namespace graftnav {

// Initial state from truth (at the start of the first IMU interval), else case.yaml
// initial_state, else data alignment (rc.alignment); the run config's GNSS selection; outages
// from `outages` when given (counted from the first IMU epoch). Notes on what was assumed are
// appended to *notes. `imu` is taken by value: a caller that needs its samples no more moves
// them into the problem instead of holding two copies.
EstimationProblem makeProblem(const CaseInputs& c, ImuSelection imu, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages,
                              std::vector<std::string>* notes);

// Starts the IMU series and the GNSS at the initial state's epoch (after an alignment): every
// estimator then starts from the same state at the same sample (the graph integrates from the
// first sample), and no GNSS epoch anchors a node before it. Notes say what was dropped.
void startAtInitialState(EstimationProblem* problem, std::vector<std::string>* notes);

}  // namespace graftnav
