#pragma once
// makeProblem for a run that reads the IMU as a file (navigate and compare when they stream):
// makeProblem sees the samples its alignment reads, never the whole recording. Given: the first
// and last samples; static: the window (alignmentPrefix); in motion: the samples through the
// alignment's levelling window around its epoch, found by reading a longer prefix until the
// epoch the alignment picks lies inside it (the GNSS is held). The problem equals the one
// makeProblem makes from the whole series, apart from its `imu` (cleared by the caller).
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/outage_schedule.h"

namespace graftnav {

// `imu.imu`: the span scanImuFile found (its first and last kept samples). Throws what
// makeProblem throws on the whole series.
EstimationProblem makeStreamedProblem(const CaseInputs& c, const ImuSelection& imu,
                                      const RunConfig& rc,
                                      const std::optional<OutageScheduleConfig>& outages,
                                      const TimeRangeConfig& range,
                                      std::vector<std::string>* notes);

}  // namespace graftnav
