#pragma once
// Outputs of `graftnav evaluate`: evaluation.json (issue 6 contract), tables.md in the seed's
// Table 2/3 layout, evaluation.csv and the per-outage CSV. Per-epoch error CSVs use navigate's
// writer (report_io.h: writeErrorsCsv).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"
#include "graftnav/sg/sg_statistics.h"

namespace graftnav::app {

struct SgSolutionErrors {
  std::string label;      // "SG1", "SG2", "REAL", "SG3"
  std::string imu_file;   // what was navigated
  Evaluation evaluation;  // against SOL_REF
};

struct SgEvaluationReport {
  std::string case_name;
  std::string estimator;
  std::string reference;  // what SOL_REF is: "truth", "reference_solution", "smoothed reference IMU (rts)"
  std::string tested_grade;
  std::vector<TimeWindow> outages;
  double outage_length_s = 0.0;
  std::vector<SgSolutionErrors> solutions;  // SG1, SG2 and REAL when present
  std::vector<std::string> notes;

  const SgSolutionErrors* find(const std::string& label) const;
  // DIFF_x per statistic, when REAL exists.
  std::optional<DriftStats> diff(const std::string& label) const;
};

// DriftStats as the JSON object S of the contract (degrees for angles).
std::string driftStatsJson(const DriftStats& s, int indent);

void writeEvaluationJson(const std::string& path, const SgEvaluationReport& r);
void writeTablesMarkdown(const std::string& path, const SgEvaluationReport& r);
void writeEvaluationCsv(const std::string& path, const SgEvaluationReport& r);
// One row per outage and solution: per-outage maxima (the peers' statistic).
void writePerOutageCsv(const std::string& path, const SgEvaluationReport& r);

}  // namespace graftnav::app
