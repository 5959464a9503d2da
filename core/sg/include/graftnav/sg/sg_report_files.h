#pragma once
// The files of an SG evaluation (`graftnav evaluate`, `real-sg`, a batch task): evaluation.json,
// tables.md in the seed's Table 2/3 layout with the predictive intervals, evaluation.csv,
// predictive.csv and the per-outage CSV. The per-epoch error CSVs use navigate's writer
// (graftnav/eval/evaluation_files.h: writeErrorsCsv).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graftnav/eval/evaluation.h"
#include "graftnav/sg/predictive.h"
#include "graftnav/sg/sg_evaluation_report.h"
#include "graftnav/sg/sg_statistics.h"

namespace graftnav {

// Sentences that say how to read the result: per SG strategy, the statistics on which ERR_REAL is
// consistent with its predictive interval and those on which grafting is optimistic or
// pessimistic; where the case cannot tell SG#1 from SG#2; what a single run's DIFF would mean.
std::vector<std::string> readingLines(const SgEvaluationReport& r);

// DriftStats as the JSON object S of the contract (degrees for angles).
std::string driftStatsJson(const DriftStats& s, int indent);

// evaluation.json's content (the Python module's evaluate) and the file.
nlohmann::json evaluationJson(const SgEvaluationReport& r);
void writeEvaluationJson(const std::string& path, const SgEvaluationReport& r);
void writeTablesMarkdown(const std::string& path, const SgEvaluationReport& r);
void writeEvaluationCsv(const std::string& path, const SgEvaluationReport& r);
// One row per outage and solution: per-outage maxima (the peers' statistic).
void writePerOutageCsv(const std::string& path, const SgEvaluationReport& r);
// One row per SG strategy and statistic: the predictive summary, REAL's percentile, DIFF interval
// and verdict.
void writePredictiveCsv(const std::string& path, const SgEvaluationReport& r);

// Every file above plus (errors_csv) errors_<LABEL>.csv per solution (at report.csv_rate_hz) into
// out_dir. errors_csv false: a streamed run wrote them as the epochs came (SgRunHooks).
void writeSgEvaluationFiles(const std::string& out_dir, const SgEvaluationReport& report,
                            bool errors_csv = true);

}  // namespace graftnav
