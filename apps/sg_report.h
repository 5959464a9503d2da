#pragma once
// Outputs of `graftnav evaluate`: evaluation.json, tables.md in the seed's Table 2/3 layout with
// the predictive intervals, evaluation.csv, predictive.csv and the per-outage CSV. Per-epoch error CSVs use navigate's
// writer (report_io.h: writeErrorsCsv).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"
#include "graftnav/sg/predictive.h"
#include "graftnav/sg/sg_statistics.h"

namespace graftnav::app {

struct SgSolutionErrors {
  std::string label;      // "SG1", "SG2", "REAL", "SG3"
  std::string imu_file;   // what was navigated (for SG: realization 0)
  // Against SOL_REF, of realization 0 at the first outage schedule: the per-epoch and per-outage
  // CSVs and the plots.
  Evaluation evaluation;
  // The reported ERR: mean over realizations (SG) and over outage schedules.
  DriftStats err_rms;       // the seed's statistic
  DriftStats err_max_rms;   // the peers' statistic
  std::vector<DriftStats> draws;  // SG only: ERR of each realization
  PredictiveStats predictive;     // SG only
  // For results built from one Evaluation (one realization, one schedule).
  static SgSolutionErrors single(const std::string& label, const std::string& imu_file, Evaluation e);
};

struct SgEvaluationReport {
  std::string case_name;
  std::string estimator;
  std::string reference;  // what SOL_REF is: "truth", "reference_solution", "smoothed reference IMU (rts)"
  std::string tested_grade;
  std::vector<TimeWindow> outages;  // of the first schedule
  double outage_length_s = 0.0;
  int realizations = 1;             // K per SG strategy
  int outage_shifts = 1;            // N schedules
  std::vector<double> shift_starts_s;  // first-outage start of each schedule (s after the first epoch)
  double static_record_s = 0.0;
  double shared_sample_fraction = 0.0;
  double csv_rate_hz = 10.0;
  std::vector<SgSolutionErrors> solutions;  // SG1, SG2 and REAL when present
  std::vector<std::string> notes;

  const SgSolutionErrors* find(const std::string& label) const;
  // DIFF_x per statistic, when REAL exists.
  std::optional<DriftStats> diff(const std::string& label) const;
};

// Sentences that say how to read the result: per SG strategy, the statistics on which ERR_REAL is
// consistent with its predictive interval and those on which grafting is optimistic or
// pessimistic; where the case cannot tell SG#1 from SG#2; what a single run's DIFF would mean.
std::vector<std::string> readingLines(const SgEvaluationReport& r);

// DriftStats as the JSON object S of the contract (degrees for angles).
std::string driftStatsJson(const DriftStats& s, int indent);

void writeEvaluationJson(const std::string& path, const SgEvaluationReport& r);
void writeTablesMarkdown(const std::string& path, const SgEvaluationReport& r);
void writeEvaluationCsv(const std::string& path, const SgEvaluationReport& r);
// One row per outage and solution: per-outage maxima (the peers' statistic).
void writePerOutageCsv(const std::string& path, const SgEvaluationReport& r);
// One row per SG strategy and statistic: the predictive summary, REAL's percentile, DIFF interval
// and verdict.
void writePredictiveCsv(const std::string& path, const SgEvaluationReport& r);

}  // namespace graftnav::app
