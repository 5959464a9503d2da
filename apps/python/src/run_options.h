#pragma once
// The run config of a Python call: a run-config file (else the case's run.yaml, as the CLI
// does), with `options` over it: a dict of run-config sections ({"ekf": {"gnss_std_floor_m":
// 0.02}}) or dotted keys ({"ekf.gnss_std_floor_m": 0.02}). Parsed and validated by core/case
// (run_config.h), so a bad value gives the CLI's message; an unknown key in `options` is an error
// (in a file it is a warning, as on the command line).
#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "graftnav/case/run_config.h"

namespace graftnav::python {

namespace py = pybind11;

// A Python value (dict, list, tuple, str, bool, int, float, None) as a YAML node. Throws
// std::invalid_argument for another type.
YAML::Node toYaml(const py::handle& value);

// An option the Python caller got wrong: raised to Python as ValueError with the library's text.
struct OptionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Throws OptionError for a bad option value or an unknown key; MissingFileError for a run-config
// file that does not exist. Warnings (unknown keys of the file) are appended to *warnings.
// `command_without_time_range` (e.g. "graftnav.evaluate"): the call does not apply a time range,
// and a time_range in the file or the options is an OptionError (requireTimeRangeUnset).
RunConfig runConfigFor(const std::string& case_dir, const std::string& run_config_path,
                       const py::object& options, std::vector<std::string>* warnings,
                       const std::string& command_without_time_range = "");

}  // namespace graftnav::python
