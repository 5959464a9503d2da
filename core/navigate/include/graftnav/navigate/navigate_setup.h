#pragma once
// The inputs of one navigation run, read and checked before any output is written: the case,
// the run config, the IMU and its profile, the GNSS, the outages and the reference. A run that
// can stream (the estimator has a streamed form) holds none of the series: the IMU, the GNSS and
// the reference are read once here, as streams, for their errors, spans and coverage, and read
// again by the run, keeping what the time range keeps (restrictToTimeRange's rule). A data
// alignment holds the samples it reads until the problem is made (streamed_problem.h); an
// in-motion alignment holds the GNSS.
#include <cstddef>
#include <string>
#include <vector>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/estimator_registry.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/navigate/navigate_request.h"
#include "graftnav/navigate/streamed_imu_file.h"

namespace graftnav {

struct NavigateSetup {
  std::string estimator;
  bool uses_gnss = true;  // false for a free-inertial run (the registry entry's uses_gnss)
  CaseInputs c;
  RunConfig rc;
  ImuSelection imu;
  OutageScheduleConfig oc;
  EstimationProblem pr;
  std::vector<std::string> notes;  // kept in run_info.json
  bool stream = false;       // the IMU read in blocks during the run; imu.imu and pr.imu not held
  bool stream_gnss = false;  // the GNSS read epoch by epoch during the run (pr.gnss_stream)
  long gnss_count = 0;       // GNSS epochs in the case
  // A streamed run's reference: not held (c.reference empty), read again as the run evaluates
  // (streamed_reference.path empty: none, or the reference is held in c.reference).
  CaseReferenceFile streamed_reference;
  ExpectedRates expected_rates;        // from the first passes over the IMU and the reference
  TimeRangeConfig time_range;          // the run config's, with the command line's bounds over it
  ImuFileScan imu_scan;                // a streamed run's: the span and counts the time range keeps
  std::size_t time_range_note_at = 0;  // where a streamed run's time-range note goes in `notes`
  bool hasReference() const { return !c.reference.empty() || !streamed_reference.path.empty(); }
};

// Reads and checks everything the run needs. Throws std::runtime_error (an unknown estimator, a
// missing file, a reader error, outages outside the data, no noise parameters for the IMU);
// warnings and the notes a user should see go to `messages`.
NavigateSetup prepareNavigate(const NavigateRequest& request, const EstimatorRegistry& registry,
                              const RunMessages& messages);

}  // namespace graftnav
