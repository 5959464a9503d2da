#pragma once
// The analysis commands a batch group can run, and what a group may say about each: the flags it
// may pass (by their command-line names, without "--"), which axes apply, what the command
// requires. The batch runs every task as a `graftnav <command>` child process, so this table is
// all it knows of the commands; a test checks it against every command's --help.
//
// The batch itself sets --out, --run-config, --estimator, --seed, --jobs and --no-plots; a group
// gives those through its own keys (run_config, estimators, seeds, plots), never as flags.

#include <optional>
#include <string>
#include <vector>

namespace graftnav {

enum class BatchCommand { kNavigate, kCompare, kReal, kRealSg, kEvaluate, kDiagnose };

// "navigate", "compare", "real", "real-sg", "evaluate", "diagnose".
const char* batchCommandName(BatchCommand command);
std::optional<BatchCommand> parseBatchCommand(const std::string& name);
const std::vector<BatchCommand>& allBatchCommands();
// "navigate, compare, real, real-sg, evaluate, diagnose", for messages.
std::string batchCommandList();

enum class FlagKind {
  kSwitch,  // true: the flag is given; false: it is not
  kValue,   // one scalar
  kList,    // a scalar or a list of scalars, passed as a comma list
  kPath,    // a file, relative to the manifest; its bytes are part of the task id
  kImu,     // ref | tested | an IMU file (as kPath when it names a file)
};

struct FlagSpec {
  std::string name;  // as on the command line without "--", e.g. "latency-grid"
  FlagKind kind;
};

struct BatchCommandSpec {
  BatchCommand command;
  std::vector<FlagSpec> flags;  // the flags a group may give
  std::vector<std::string> required_flags;
  std::vector<std::string> default_estimators;
  bool estimators_in_one_task = false;  // compare: one task runs every estimator of the group
  bool estimator_optional = false;      // diagnose: a group without estimators runs the finder only
  bool takes_seed = false;              // --seed (grafting)
  bool takes_jobs = false;              // --jobs (set to 1: tasks run side by side instead)
  bool requires_run_config = false;
  // Whether it applies the run config's time_range (navigate, compare, real); the others refuse a run
  // config or an option that sets one (requireTimeRangeUnset) when the manifest is read.
  bool applies_time_range = false;
  // Files it writes that the batch reads back (docs/outputs.md), in the order it reads them.
  std::vector<std::string> result_files;
};

const BatchCommandSpec& batchCommandSpec(BatchCommand command);
// The flag of that name, or null.
const FlagSpec* findFlag(const BatchCommandSpec& spec, const std::string& name);

}  // namespace graftnav
