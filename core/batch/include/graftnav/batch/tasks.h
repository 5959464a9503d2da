#pragma once
// The tasks of a batch manifest, in a fixed order, each with a stable id, its own output folder
// and the command line of its child process.
//
// Order: groups as listed; inside a group cases > estimators > option values (a grid, the last
// key fastest) > outage schedules > seeds. A task's index is its place in that order.
//
// Id: 16 hex digits (task_id.h) over everything that decides the result: graftnav's version, the
// task's folder, the command, the case's name and the bytes of every file under the case folder,
// the estimator(s), the schedule's numbers, the seed, the option values, the bytes of the run
// config, the flags and the bytes of every file a flag names, the plots switch. Files a case.yaml
// names outside its own folder are not hashed.

#include <optional>
#include <string>
#include <vector>

#include "graftnav/batch/manifest.h"
#include "graftnav/batch/run_config_overrides.h"

namespace graftnav {

struct BatchTask {
  int index = 0;    // position in the manifest's expansion order (0-based)
  std::string id;   // 16 hex digits (empty for tasks outside the range that was hashed)
  int group = 0;    // index into BatchManifest::groups
  std::string grp;  // the group's name
  BatchCommand command = BatchCommand::kEvaluate;
  std::string case_dir, case_name;
  std::string estimator;                       // "ekf"; compare: "ekf+rts"; no estimator: "none"
  std::vector<std::string> estimators;         // what --estimator gets (empty: none)
  std::optional<OutageScheduleSpec> schedule;  // empty: the run config's schedule
  std::string schedule_label;                  // "config" when empty
  std::optional<unsigned long long> seed;      // empty: the command takes none
  std::vector<RunConfigSetting> options;       // this task's option values
  std::string options_json;                    // {"fgo.window_nodes":5}; "{}" without options
  std::string name;     // "<case>__<estimator>__<schedule>[__seed<N>][__<key>=<value>...]"
  std::string out_dir;  // <manifest out>/tasks/<grp>/<name>
  std::string folder() const { return grp + "/" + name; }  // unique within the manifest
};

// graftnav's project version, part of every id.
const char* batchSoftwareVersion();

// Expands the manifest and gives every task its id. Throws naming the manifest, both groups'
// lines and the folder when two tasks would write one folder, and naming a file that cannot be
// read.
std::vector<BatchTask> expandBatchTasks(const BatchManifest& manifest);
// The tasks without ids (cheap: no file is read), and the ids of only some of them (an array
// element needs no more, and hashing reads every byte of the cases).
std::vector<BatchTask> expandBatchTaskList(const BatchManifest& manifest);
void assignTaskIds(const BatchManifest& manifest, const std::vector<std::size_t>& which,
                   std::vector<BatchTask>* tasks);

// The run config file the task's command reads: none (empty), the group's file, or, when the task
// sets option values or a schedule, <out_dir>/run_config.yaml (written by writeTaskRunConfig).
std::string taskRunConfigPath(const BatchManifest& manifest, const BatchTask& task);
// Writes <out_dir>/run_config.yaml when the task needs one of its own.
void writeTaskRunConfig(const BatchManifest& manifest, const BatchTask& task);

// The child process's argv: graftnav_exe, the command, the case, --out and the rest.
std::vector<std::string> taskCommandLine(const BatchManifest& manifest, const BatchTask& task,
                                         const std::string& graftnav_exe);

}  // namespace graftnav
