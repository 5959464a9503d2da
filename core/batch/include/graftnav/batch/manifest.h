#pragma once
// The manifest of `graftnav batch`, parsed in one place (docs/batch.md). Paths are relative to the
// manifest.
//
//   out: results/                 # results.sqlite, summaries, reports, tasks/, slurm/
//   jobs: 0                       # tasks in parallel; 0 = all cores
//   groups:
//     - command: real             # navigate | compare | real | real-sg | evaluate | diagnose
//       name: wid                 # optional: the tasks' folder tasks/<name>/ (default: command)
//       cases: [drives/wid_*]     # folders or globs, each sorted
//       estimators: [ekf, rts]    # a task per estimator (compare: one task runs them all)
//       seeds: [1, 2, 3]          # evaluate, real-sg: a task per grafting seed (or seed: 1)
//       outage_schedules:         # a task per schedule; default: the run config's
//         - {length_s: 60, period_s: 180, start_s: 300}
//       run_config: ../configs/real/wid_car.yaml   # `config:` is an alias
//       flags: {profile: ../configs/real/wid_mrup.yaml, lenient: true}
//       options:                  # a grid over run-config keys (dotted paths)
//         ekf.gate_probability: [0.99, 0.999]
//       plots: false              # per-task plots (default false: a batch is for tables)
//
// A manifest without `groups` holds one evaluate group at its top level (config, seed(s), plots,
// cases, estimators, outage_schedules), the layout of earlier versions.
//
// Everything a group says is checked here, before any task runs: the command, each flag against
// the command's table (command_table.h), each glob (it must match a folder), each option key and
// value against the run-config schema, names that would give two tasks one folder. Errors throw
// std::runtime_error naming the manifest file and line.

#include <optional>
#include <string>
#include <vector>

#include "graftnav/batch/command_table.h"

namespace graftnav {

struct OutageScheduleSpec {
  double length_s = 60.0, period_s = 180.0, start_s = 300.0;
  std::string label() const;  // e.g. "60s-every-180s-from-300s"
};

struct BatchCase {
  std::string path;  // resolved against the manifest
  std::string name;  // the folder's name, unique within the group
  int line = 0;      // of the `cases` entry it came from
};

struct BatchFlag {
  std::string name;  // without "--"
  FlagKind kind = FlagKind::kValue;
  std::vector<std::string> values;  // switch: none; list: each; others: one (a path resolved)
  bool is_file = false;             // a path (or an IMU file): its bytes enter the task id
  int line = 0;
};

// One run-config key and the values it takes, as YAML text ("0.999", "[4, 5]").
struct OptionAxis {
  std::string key;  // dotted path, e.g. "fgo.window_nodes"
  std::vector<std::string> values;
  std::vector<int> lines;  // of each value
  int line = 0;            // of the key
};

struct BatchGroup {
  std::string name;  // the `grp` of its tasks: `name:` or the command's name
  BatchCommand command = BatchCommand::kEvaluate;
  int line = 0;  // where the group starts
  std::vector<BatchCase> cases;
  std::vector<std::string> estimators;        // empty: diagnose without navigation
  std::vector<unsigned long long> seeds;      // empty: the command takes no seed
  std::vector<OutageScheduleSpec> schedules;  // empty: the run config's schedule
  std::string run_config;                     // resolved path; empty: none
  std::vector<BatchFlag> flags;
  std::vector<OptionAxis> options;
  bool plots = false;
};

struct BatchManifest {
  std::string path;
  std::string out_dir;
  int jobs = 0;
  std::vector<BatchGroup> groups;
};

// Throws std::runtime_error naming the file, line and key for anything the manifest gets wrong.
BatchManifest loadBatchManifest(const std::string& path);

// The folder name of a case path, ignoring a trailing '/' ("data/good/" -> "good").
std::string caseName(const std::string& case_path);

}  // namespace graftnav
