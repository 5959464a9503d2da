#pragma once
// The run config a task runs with: the group's run config with the task's option values and outage
// schedule written over it at their dotted keys ("fgo.window_nodes"), as YAML text that the task's
// command reads with --run-config. The manifest's option values are checked here too, before any
// task runs.

#include <string>
#include <vector>

#include "graftnav/case/run_config.h"

namespace graftnav {

struct RunConfigSetting {
  std::string key;         // dotted path
  std::string value_yaml;  // the value as YAML text ("0.999", "[4, 5]")
};

// The base file (empty path: an empty config) with every override set, creating the sections it
// needs (a map value merges into a map already there), emitted as YAML. Throws std::runtime_error naming the file when it cannot be read or a
// key runs through a value that is not a map.
std::string composeRunConfig(const std::string& base_path,
                             const std::vector<RunConfigSetting>& overrides);

// Throws std::runtime_error with the reason when `value_yaml` is not a valid value of `key` in a
// run config (an unknown section or key, a value of the wrong type or out of range): the base file
// is parsed and the value applied by the run config's own parser (core/case), so the batch holds
// no copy of the schema. A map value sets a section's keys over the base's ("outages" ->
// {length_s: 30}). Returns the run config with the value applied.
RunConfig checkRunConfigOption(const std::string& base_path, const std::string& key,
                               const std::string& value_yaml);

// Whether the file lists explicit outage windows (outages.windows), which a schedule cannot
// replace.
bool runConfigListsOutageWindows(const std::string& base_path);

}  // namespace graftnav
