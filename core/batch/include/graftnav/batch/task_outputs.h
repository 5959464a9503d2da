#pragma once
// The files a task's command wrote, read back into the rows of the results database: errors.json
// (navigate), compare.json (compare), summary.json (real), evaluation.json and outage_drift.csv
// (evaluate, real-sg), diagnosis.json (diagnose). One name per quantity whatever the file calls
// it: horizontal_m, vertical_m, roll_deg, pitch_deg, heading_deg (run_record.h).

#include <string>
#include <vector>

#include "graftnav/batch/command_table.h"
#include "graftnav/batch/run_record.h"

namespace graftnav {

// Fills record->statistics and the other rows from the task's folder. `estimators` are the
// task's (the label of the rows of commands whose files do not name it). Throws
// std::runtime_error naming the file when a file the command must write is missing or is not the
// JSON it should be. A command that reports a failure inside its files (real's "failed" list)
// sets record->ok = false and record->error.
void readTaskOutputs(BatchCommand command, const std::string& out_dir,
                     const std::vector<std::string>& estimators, BatchRunRecord* record);

// "SG#1", "IMU_SG1", "SG1" -> "SG1"; other labels unchanged.
std::string solutionLabel(const std::string& label);

// evaluation.json's predictive block and realization count (empty when the file has none).
struct BatchPredictive {
  std::optional<int> realizations;
  std::vector<BatchPredictiveRow> rows;
};
BatchPredictive readPredictive(const std::string& evaluation_json_path);

}  // namespace graftnav
