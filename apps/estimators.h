#pragma once
// Estimators by name: one table, name -> function(problem, run config, progress) -> NavSolution.
// To add one, append an entry in estimators.cpp (e.g. "fgo", "fgo-window").

#include <functional>
#include <string>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/filters/solution_sink.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "run_config.h"

namespace graftnav::app {

using EstimatorFn =
    std::function<NavSolution(const EstimationProblem&, const RunConfig&, const ProgressFn&)>;

// The streamed form: samples from `imu` (problem.imu is not read), output epochs into `sink`,
// the GNSS bookkeeping returned. Same epochs as the in-memory form, memory not growing with the
// recording (see docs/BENCHMARKS.md).
struct ImuStream {
  ImuPassFn pass;  // one pass over the samples; may be called more than once
};
using StreamingEstimatorFn = std::function<NavSolution(const EstimationProblem&, const ImuStream&,
                                                       const RunConfig&, SolutionSink&)>;

struct EstimatorEntry {
  std::string name;
  std::string description;
  EstimatorFn run;
  StreamingEstimatorFn stream;  // empty when the estimator holds its input in memory
};

const std::vector<EstimatorEntry>& estimatorTable();
std::vector<std::string> estimatorNames();
// Throws std::invalid_argument listing the known names when `name` is not in the table.
NavSolution runEstimator(const std::string& name, const EstimationProblem& problem,
                         const RunConfig& config, const ProgressFn& progress = {});

// True when `name` has a streamed form; throws like runEstimator for an unknown name.
bool canStream(const std::string& name);

// An IMU file read in blocks (ImuBlockReader; options.nominal_rate_hz > 0); each pass reads the
// file again. *report (when given) receives the last pass's
// reader report.
ImuStream imuFileStream(const std::string& path, const ImuReadOptions& options,
                        ReadReport* report = nullptr);

// GNSS files read one epoch at a time (GnssStreamReader) as a problem's gnss_stream; each pass
// reads them again. fixtype_path empty: no fix-type file.
GnssOpenFn gnssFileStream(const std::string& pos_path, const std::string& fixtype_path,
                          const GnssReadPolicy& policy);

// Runs the streamed form of `name`; throws std::invalid_argument when it has none.
NavSolution runEstimatorStreaming(const std::string& name, const EstimationProblem& problem,
                                  const ImuStream& imu, const RunConfig& config,
                                  SolutionSink& sink);

}  // namespace graftnav::app
