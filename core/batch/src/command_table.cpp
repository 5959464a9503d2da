#include "graftnav/batch/command_table.h"

#include <stdexcept>

namespace graftnav {
namespace {

using K = FlagKind;

std::vector<BatchCommandSpec> makeTable() {
  std::vector<BatchCommandSpec> t;
  BatchCommandSpec navigate;
  navigate.command = BatchCommand::kNavigate;
  navigate.flags = {{"imu", K::kImu},        {"profile", K::kPath}, {"decimate", K::kValue},
                    {"lenient", K::kSwitch}, {"start", K::kValue},  {"end", K::kValue}};
  navigate.default_estimators = {"ekf"};
  navigate.applies_time_range = true;
  navigate.result_files = {"errors.json", "run_info.json", "outage_drift.csv"};
  t.push_back(navigate);

  BatchCommandSpec compare;
  compare.command = BatchCommand::kCompare;
  compare.flags = {{"imu", K::kImu},           {"profile", K::kPath}, {"lenient", K::kSwitch},
                   {"no-outages", K::kSwitch}, {"start", K::kValue},  {"end", K::kValue}};
  compare.default_estimators = {"ekf", "rts"};
  compare.applies_time_range = true;
  compare.estimators_in_one_task = true;
  compare.result_files = {"compare.json"};
  t.push_back(compare);

  BatchCommandSpec real;
  real.command = BatchCommand::kReal;
  real.flags = {
      {"imu", K::kImu},           {"profile", K::kPath},       {"latency-scan", K::kSwitch},
      {"latency-grid", K::kList}, {"latency-types", K::kList}, {"latency-estimators", K::kList},
      {"start", K::kValue},       {"end", K::kValue}};
  real.default_estimators = {"ekf"};
  real.applies_time_range = true;
  real.requires_run_config = true;
  real.result_files = {"summary.json"};
  t.push_back(real);

  BatchCommandSpec real_sg;
  real_sg.command = BatchCommand::kRealSg;
  real_sg.flags = {{"ref-profile", K::kPath},
                   {"tested-profile", K::kPath},
                   {"realizations", K::kValue},
                   {"static-gyro-threshold", K::kValue},
                   {"static-accel-threshold", K::kValue},
                   {"min-static", K::kValue},
                   {"max-static-speed", K::kValue}};
  real_sg.required_flags = {"ref-profile", "tested-profile"};
  real_sg.default_estimators = {"rts"};
  real_sg.takes_seed = true;
  real_sg.takes_jobs = true;
  real_sg.requires_run_config = true;
  real_sg.result_files = {"evaluation.json", "outage_drift.csv"};
  t.push_back(real_sg);

  BatchCommandSpec evaluate;
  evaluate.command = BatchCommand::kEvaluate;
  evaluate.flags = {{"sol-ref", K::kValue},
                    {"realizations", K::kValue},
                    {"outage-shifts", K::kValue},
                    {"no-cross-axis", K::kSwitch}};
  evaluate.default_estimators = {"ekf"};
  evaluate.takes_seed = true;
  evaluate.takes_jobs = true;
  evaluate.result_files = {"evaluation.json", "outage_drift.csv"};
  t.push_back(evaluate);

  BatchCommandSpec diagnose;
  diagnose.command = BatchCommand::kDiagnose;
  diagnose.flags = {{"options", K::kPath}, {"tested-profile", K::kPath}};
  diagnose.estimator_optional = true;
  diagnose.result_files = {"diagnosis.json"};
  t.push_back(diagnose);
  return t;
}

const std::vector<BatchCommandSpec>& table() {
  static const std::vector<BatchCommandSpec> t = makeTable();
  return t;
}

}  // namespace

const char* batchCommandName(BatchCommand command) {
  switch (command) {
    case BatchCommand::kNavigate:
      return "navigate";
    case BatchCommand::kCompare:
      return "compare";
    case BatchCommand::kReal:
      return "real";
    case BatchCommand::kRealSg:
      return "real-sg";
    case BatchCommand::kEvaluate:
      return "evaluate";
    case BatchCommand::kDiagnose:
      return "diagnose";
  }
  throw std::logic_error("batchCommandName: unknown command");
}

const std::vector<BatchCommand>& allBatchCommands() {
  static const std::vector<BatchCommand> all{BatchCommand::kNavigate, BatchCommand::kCompare,
                                             BatchCommand::kReal,     BatchCommand::kRealSg,
                                             BatchCommand::kEvaluate, BatchCommand::kDiagnose};
  return all;
}

std::optional<BatchCommand> parseBatchCommand(const std::string& name) {
  for (BatchCommand c : allBatchCommands())
    if (name == batchCommandName(c)) return c;
  return std::nullopt;
}

std::string batchCommandList() {
  std::string s;
  for (BatchCommand c : allBatchCommands())
    s += (s.empty() ? "" : ", ") + std::string(batchCommandName(c));
  return s;
}

const BatchCommandSpec& batchCommandSpec(BatchCommand command) {
  for (const auto& s : table())
    if (s.command == command) return s;
  throw std::logic_error("batchCommandSpec: unknown command");
}

const FlagSpec* findFlag(const BatchCommandSpec& spec, const std::string& name) {
  for (const auto& f : spec.flags)
    if (f.name == name) return &f;
  return nullptr;
}

}  // namespace graftnav
