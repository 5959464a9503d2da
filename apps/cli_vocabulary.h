#pragma once
// The flag vocabulary every subcommand shares (docs/cli.md): --estimator (a comma list),
// --run-config / --sim-config, --imu (default ref), --lenient, --no-plots, --start / --end, and
// the old spellings kept as hidden aliases that print a deprecation warning. Also the rules for
// paths given on the command line: relative paths are tried against the case, then the current
// folder, and the error names every path tried.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/case/run_config.h"

namespace graftnav::app {

// --imu on every command that navigates one IMU of a case: the given choice, else the case's
// reference IMU, else its only IMU (chooseImu of graftnav/case/case_inputs.h), said on stderr.
std::string imuChoice(const std::string& given, const std::string& case_dir);

// "ekf, rts" -> {"ekf", "rts"}; throws std::invalid_argument for an empty list or entry.
std::vector<std::string> splitEstimatorList(const std::string& list);

// A hidden option `old_name` that sets *target like `new_name` does, after printing
// "warning: OLD is deprecated, use NEW" on stderr.
void addDeprecatedOption(CLI::App* cmd, const std::string& old_name, const std::string& new_name,
                         std::string* target);
void addDeprecatedOption(CLI::App* cmd, const std::string& old_name, const std::string& new_name,
                         std::vector<std::string>* target);  // a comma list
void addDeprecatedFlag(CLI::App* cmd, const std::string& old_name, const std::string& new_name,
                       bool* target);

// For an option that is required but may come through a deprecated alias: throws
// CLI::RequiredError naming `flag` when `value` is empty (call first in the callback).
void requireValue(const std::string& value, const std::string& flag);

// --start / --end (GNSS seconds of week) into a time range (mergeTimeRange of
// graftnav/case/run_config.h lays it over the run config's).
void addTimeRangeOptions(CLI::App* cmd, TimeRangeConfig* range);

// A path given by the user: absolute as is; relative, tried against case_dir first, then the
// current folder. Throws std::runtime_error "<what> 'p' not found; tried 'a', 'b'".
std::string resolveUserPath(const std::string& path, const std::string& case_dir,
                            const std::string& what);

// The run config of a case run: the given file (resolved as above), else CASE/run.yaml when it
// exists (written by `graftnav import`), else none (empty string).
std::string runConfigPathFor(const std::string& given, const std::string& case_dir);

}  // namespace graftnav::app
