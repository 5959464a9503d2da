#include "run_options.h"

#include <filesystem>

#include "graftnav/io/file_errors.h"

namespace graftnav::python {

YAML::Node toYaml(const py::handle& value) {
  if (value.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (py::isinstance<py::dict>(value)) {
    YAML::Node map(YAML::NodeType::Map);
    for (const auto& kv : py::reinterpret_borrow<py::dict>(value))
      map[py::str(kv.first).cast<std::string>()] = toYaml(kv.second);
    return map;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& item : value) seq.push_back(toYaml(item));
    return seq;
  }
  if (py::isinstance<py::bool_>(value)) return YAML::Node(value.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::int_>(value)) return YAML::Node(py::str(value).cast<std::string>());
  if (py::isinstance<py::float_>(value))  // repr: the shortest text that reads back the same double
    return YAML::Node(py::repr(value).cast<std::string>());
  if (py::isinstance<py::str>(value)) return YAML::Node(value.cast<std::string>());
  throw std::invalid_argument("options: a value of type " +
                              py::str(value.get_type().attr("__name__")).cast<std::string>() +
                              " is not a run-config value (dict, list, str, bool, int, float)");
}

RunConfig runConfigFor(const std::string& case_dir, const std::string& run_config_path,
                       const py::object& options, std::vector<std::string>* warnings,
                       const std::string& command_without_time_range) {
  std::string path = run_config_path;
  if (path.empty() && !case_dir.empty()) {
    const auto own = std::filesystem::path(case_dir) / "run.yaml";
    if (std::filesystem::is_regular_file(own)) path = own.string();
  }
  RunConfig rc;
  // A time range the call does not apply, named with the file or the options that set it.
  const auto refuse_time_range = [&](const std::string& source) {
    if (command_without_time_range.empty()) return;
    try {
      requireTimeRangeUnset(rc.time_range, source, command_without_time_range);
    } catch (const std::exception& e) {
      throw OptionError(e.what());
    }
  };
  try {
    if (!path.empty()) rc = loadRunConfig(path, warnings);
  } catch (const MissingFileError&) {
    throw;
  } catch (const std::exception& e) {
    throw OptionError(e.what());
  }
  refuse_time_range(path);
  if (options.is_none()) return rc;
  if (!py::isinstance<py::dict>(options))
    throw OptionError("options: expected a dict of run-config sections or dotted keys");
  std::vector<RunConfigOverride> overrides;
  for (const auto& kv : py::reinterpret_borrow<py::dict>(options))
    overrides.emplace_back(py::str(kv.first).cast<std::string>(), toYaml(kv.second));
  RunConfigReport report;
  try {
    rc = applyRunConfigOverrides(rc, overrides, "options", &report);
  } catch (const std::exception& e) {
    throw OptionError(e.what());
  }
  if (!report.unknown_keys.empty()) {
    std::string keys;
    for (const auto& k : report.unknown_keys) keys += (keys.empty() ? "'" : ", '") + k + "'";
    throw OptionError("options: unknown key " + keys +
                      " (run-config sections: " + "see configs/navigate.yaml)");
  }
  refuse_time_range("options");
  return rc;
}

}  // namespace graftnav::python
