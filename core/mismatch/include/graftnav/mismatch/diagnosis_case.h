#pragma once
// The finder's inputs from a case folder loaded by core/case (`graftnav diagnose`).
#include <functional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/mismatch/diagnosis.h"

namespace graftnav {

struct DiagnosisCaseOptions {
  std::string tested_profile;     // an IMU profile file whose plausible_ranges replace case.yaml's
  bool navigation_level = false;  // the navigation level runs too (it holds the reference)
};
using DiagnosisLog = std::function<void(const std::string&)>;

// The finder's inputs from the loaded case: records, plausible ranges, and the simulation with
// its priors (SG#2 from the lab data, or the static-bias simulation without). The records are
// moved out of the selections, so the case holds each IMU series once; a tested selection read
// without its samples (selectImu's read_samples = false) is read from its file as passes
// (DiagnosisInputs::real_recording, spooled once), or whole for the static-bias simulation. The truth (the attitude
// along the record) is handed over when the finder needs it: read from its file, or copied from
// the case when the navigation level holds it.
// With lab data (lab/static.txt) the lab static record must pass the grafting floor
// (checkLabStaticRecord); throws std::runtime_error otherwise. Warnings and progress go to log.
DiagnosisInputs diagnosisInputsOf(CaseInputs& c, const RunConfig& rc, ImuSelection* ref_imu,
                                  ImuSelection* tested, const DiagnosisCaseOptions& options,
                                  std::vector<std::string>* notes, const DiagnosisLog& log);

}  // namespace graftnav
