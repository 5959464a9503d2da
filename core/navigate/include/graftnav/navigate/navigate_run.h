#pragma once
// One navigation run on checked inputs (navigate_setup.h): the estimator of the registry run
// streamed (the IMU read in blocks, the per-epoch files written and the epochs evaluated against
// the reference as they come, memory flat with the recording) or in memory, then the evaluation
// files. Both ways write byte-identical files into the output folder:
//   solution.nav, imu_errors.txt, state_std.txt, odometer_scale.txt   (per epoch)
//   errors.json, errors.csv, outage_drift.csv                         (with a reference)
//   run_info.json                                                     (always)
// docs/outputs.md describes each file.
#include <optional>
#include <string>

#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/navigate/navigate_request.h"
#include "graftnav/navigate/navigate_setup.h"
#include "graftnav/navigate/solution_file_sink.h"

namespace graftnav {

struct NavigateOutcome {
  // In memory: the whole solution; streamed: the GNSS bookkeeping and the last odometer scale
  // only (no states).
  NavSolution solution;
  RunFiles files;
  double run_time_s = 0.0;               // the estimator and its per-epoch files
  std::optional<Evaluation> evaluation;  // when the case has a reference
};

// Runs setup.estimator and writes every file into out_dir (which must exist). Throws before the
// per-epoch files are committed when the run used no GNSS although it should have (checkGnssUsed).
// Warnings go to `messages` and into run_info.json's notes; progress is called by an in-memory
// run.
NavigateOutcome runNavigate(const NavigateSetup& setup, const std::string& out_dir,
                            const EstimatorRegistry& registry, const RunMessages& messages,
                            const ProgressFn& progress = {});

}  // namespace graftnav
