#pragma once
// The SG evaluation's files and console summary, shared by `evaluate` and `real-sg`: the run
// itself is the library's (graftnav/case/sg_case_evaluation.h).
#include <functional>
#include <string>

#include "graftnav/sg/sg_evaluation_report.h"

namespace graftnav::app {

using LogFn = std::function<void(const std::string&)>;

// The console summary of `evaluate` and `real-sg`: ERR with intervals, REAL's percentile and
// verdict, DIFF and the reading sentences (cmd_evaluate.cpp).
void printEvaluationSummary(const SgEvaluationReport& report);

// evaluation.json, tables.md, evaluation.csv, predictive.csv, outage_drift.csv, errors_<LABEL>.csv
// and (plots) the plots of a report into out_dir. errors_csv false: the errors_<LABEL>.csv were
// written as the epochs came (the report holds no epochs).
void writeSgOutputs(const std::string& out_dir, const SgEvaluationReport& report, bool plots,
                    const LogFn& log, bool errors_csv = true);

}  // namespace graftnav::app
