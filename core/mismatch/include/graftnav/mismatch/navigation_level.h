#pragma once
// The navigation level of `graftnav diagnose --estimator E`: SG#2, SG#3 and REAL (the tested IMU's
// recording) navigated with one estimator and outage schedule and evaluated against SOL_REF
// (truth, the case's reference solution, or the RTS-smoothed reference IMU), and the outage
// shares of |ERR_SG2 - ERR_REAL| in outages.csv.
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/mismatch/diagnosis_report.h"

namespace graftnav {

// Throws std::runtime_error when the case cannot be navigated (no GNSS, no SOL_REF). Notes on
// what was assumed go to *notes.
NavigationComparison compareNavigation(const CaseInputs& c, const ImuSelection& tested,
                                       const std::string& estimator, const RunConfig& rc,
                                       const OutageOverrides& outages, const ImuSeries& sg2,
                                       const ImuSeries& sg3, const EstimatorRegistry& estimators,
                                       std::vector<std::string>* notes);

// out_dir/outages.csv: per outage window the maximum horizontal drift of SG#2, SG#3 and REAL and
// the window's share of sum |SG2 - REAL|.
void writeNavigationOutagesCsv(const std::string& out_dir, const NavigationComparison& nav);

}  // namespace graftnav
