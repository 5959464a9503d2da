#pragma once
// A real recording read for `graftnav real` and `real-sg`: the lenient read policies, every
// reader repair and warning given, and the estimator inputs started at the initial state's epoch
// (every estimator starts from the same state at the same sample).
//
// `real` streams when every estimator has a streamed form and no latency study needs the series:
// the IMU, the GNSS (without a gnss: section nor an in-motion alignment) and the reference
// solution are then read once here for their errors, spans and rates, and read again by each run
// (real_run.h); only the check points inside the outages are held, and the samples a data
// alignment reads until the problem is made (streamed_problem.h; an in-motion alignment holds
// the GNSS). A time range keeps, streamed or held, what restrictToTimeRange keeps: the files are
// cut as they are read (streamed_imu_file.h), and the check points are the kept fixes.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/navigate/navigate_request.h"
#include "graftnav/navigate/streamed_imu_file.h"

namespace graftnav {

// Loads the case with the real read policies (what `options` asks to load; lenient always) and
// gives every reader condition as a note.
CaseInputs loadRealCase(const std::string& dir, CaseLoadOptions options,
                        const RunMessages& messages);

// One IMU of the case ("ref", "tested" or a file) with the profile file; notes the reader's
// conditions. read_samples false: the file is read once through the block reader for its errors
// and its repairs, and `imu` holds the first and last samples `range` keeps only (*scan: that
// read's counts).
ImuSelection selectRealImu(const CaseInputs& c, const std::string& which,
                           const std::string& profile, bool read_samples,
                           const RunMessages& messages, const TimeRangeConfig& range = {},
                           ImuFileScan* scan = nullptr);

// makeProblem, then startAtInitialState (graftnav/case/problem.h). The notes go to `messages`
// (with the alignment's heading against case.yaml's) and to *notes when given.
EstimationProblem makeRealProblem(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                                  const std::optional<OutageScheduleConfig>& outages,
                                  const RunMessages& messages,
                                  std::vector<std::string>* notes = nullptr);

struct RealRequest {
  std::string case_dir;
  std::string run_config;  // run config YAML with an outages: section
  std::string imu = "ref";
  std::string profile_path;  // IMU profile YAML; empty: the one case.yaml names
  std::vector<std::string> estimators{"ekf", "rts", "fgo"};
  bool latency_study = false;  // a latency scan or grid follows: the series are held
  TimeRangeConfig time_range;  // --start/--end, over the run config's time_range:
};

struct RealInputs {
  RunConfig rc;
  // The part of the recording navigated (the run config's, the request's bounds over it): the
  // IMU samples, the GNSS fixes and the check points it keeps (restrictToTimeRange's rule).
  TimeRangeConfig time_range;
  CaseInputs c;                 // streamed: without its reference, and without its GNSS when
                                // the run reads the file (pr.gnss_stream)
  CaseReferenceFile reference;  // streamed: the reference solution, read again by each run
  long reference_epochs = 0;
  ImuSelection imu;      // streamed: no samples (imu.path read in blocks by each run)
  ImuFileScan imu_scan;  // streamed: the read of the IMU file for its errors, span and counts
  EstimationProblem pr;
  bool stream = false;
  // Streamed: IMU samples whose interval starts before this time are skipped as they are read
  // (what startAtInitialState cuts from a held series); -inf: none.
  double imu_start_s = -std::numeric_limits<double>::infinity();
  ExpectedRates expected_rates;  // streamed: from the first passes over the IMU and the reference
  // The GNSS epochs of gnss.checkpoint_fix_types (time tags corrected like the navigation's);
  // streamed: only those inside the outages.
  GnssSeries checkpoints;
  long checkpoint_epochs = 0;  // all of them
  int checkpoints_in_outages = 0;
  double t_first_s = 0.0;  // the start of the IMU's first interval
  bool hasReference() const { return stream ? reference_epochs > 0 : !c.reference.empty(); }
};

// Reads and checks the inputs of `graftnav real`. Throws std::runtime_error (a missing file, a
// reader error, no outages: section, no noise parameters for the IMU, a range that keeps no
// sample, a range with a latency study, which reads the fixes and the reference beyond it). An
// unknown estimator is not an error here: its run fails and is listed.
RealInputs loadRealInputs(const RealRequest& request, const EstimatorRegistry& registry,
                          const RunMessages& messages);

}  // namespace graftnav
