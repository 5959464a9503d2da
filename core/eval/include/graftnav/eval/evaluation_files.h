#pragma once
// The files that hold the evaluation of a navigation run: errors.json (the result contract),
// run_info.json (everything else worth keeping: NEES band, GNSS counts, provenance), errors.csv
// (per-epoch errors) and outage_drift.csv (per-outage maxima). docs/outputs.md lists their fields.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graftnav/eval/evaluation.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/io/json_result.h"

namespace graftnav {

struct ReportMeta {
  std::string estimator;
  std::string imu;  // name of the IMU navigated (profile name, or "ref"/"tested")
  int outage_count = 0;
  double outage_length_s = 0.0;  // nominal length (0 when none)
};

// Why the statistics of `ev` that are NaN could not be computed ("" when all are finite).
std::string missingStatisticsReason(const Evaluation& ev);

// errors.json, exactly: {"estimator", "imu", "outages": {"count", "length_s"}, "overall": {...},
// "outage": S, "outage_max": S, "nees"}; degrees for angles, a statistic that cannot be computed
// written as null (errorsJson: the object; the Python module's statistics). writeErrorsJson
// returns the warnings of writeJsonResult (graftnav/io/json_result.h).
nlohmann::json errorsJson(const ReportMeta& meta, const Evaluation& ev);
std::vector<std::string> writeErrorsJson(const std::string& path, const ReportMeta& meta,
                                         const Evaluation& ev);
// run_info.json: NEES band and sample count, GNSS used/rejected/withheld, outage windows, notes.
// Returns the warnings of writeJsonResult.
std::vector<std::string> writeRunInfoJson(const std::string& path, const ReportMeta& meta,
                                          const Evaluation& ev, const NavSolution& sol,
                                          const std::vector<TimeWindow>& outages,
                                          const std::vector<std::string>& notes, double run_time_s);
// Per-epoch errors every `min_interval_s` (0: every epoch); columns carry their units.
void writeErrorsCsv(const std::string& path, const Evaluation& ev, double min_interval_s);
// One row per outage: window and maxima.
void writeOutageCsv(const std::string& path, const Evaluation& ev);

}  // namespace graftnav
