#include "graftnav/batch/run_config_overrides.h"

#include <yaml-cpp/yaml.h>

#include <sstream>
#include <stdexcept>

#include "graftnav/case/run_config.h"
#include "graftnav/io/yaml_fields.h"

namespace graftnav {
namespace {

std::vector<std::string> splitKey(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string p;
  while (std::getline(ss, p, '.')) parts.push_back(p);
  if (parts.empty()) throw std::runtime_error("an empty run-config key");
  return parts;
}

YAML::Node loadBase(const std::string& base_path) {
  if (base_path.empty()) return YAML::Node(YAML::NodeType::Map);
  YAML::Node root = yaml_fields::loadFile(base_path);
  if (!root.IsDefined() || root.IsNull()) return YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw std::runtime_error(base_path + ": the run config must be a YAML map");
  return root;
}

// Writes `value` at `node[key]`; a map given where a map is merges key by key (an option
// `outages: {length_s: 30}` keeps the group's other outages keys), as the run-config parser does
// with overrides.
void setMerged(YAML::Node node, const std::string& key, const YAML::Node& value) {
  YAML::Node cur = node[key];
  if (value.IsMap() && cur.IsDefined() && cur.IsMap()) {
    for (const auto& kv : value) setMerged(cur, kv.first.Scalar(), kv.second);
    return;
  }
  node[key] = value;
}

void setDotted(YAML::Node root, const std::string& key, const std::string& value_yaml) {
  const std::vector<std::string> parts = splitKey(key);
  YAML::Node cur = root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = cur[parts[i]];
    if (!next.IsDefined() || next.IsNull()) {
      cur[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = cur[parts[i]];
    } else if (!next.IsMap()) {
      throw std::runtime_error("'" + key + "': '" + parts[i] + "' holds a value, not a section");
    }
    cur.reset(next);  // rebinds cur (operator= would assign the value)
  }
  setMerged(cur, parts.back(), YAML::Load(value_yaml));
}

RunConfig parseBase(const std::string& base_path) {
  if (base_path.empty()) return RunConfig{};
  return loadRunConfig(base_path);
}

std::string knownKeys(const std::string& key) {
  const std::string section = splitKey(key).front();
  std::string sections;
  for (const auto& [name, keys] : runConfigSchema()) {
    if (name == section) {
      std::string list;
      for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
      return "the keys of " + section + ": " + list;
    }
    sections += (sections.empty() ? "" : ", ") + name;
  }
  return "the sections: " + sections;
}

}  // namespace

std::string composeRunConfig(const std::string& base_path,
                             const std::vector<RunConfigSetting>& overrides) {
  YAML::Node root = YAML::Clone(loadBase(base_path));
  for (const auto& o : overrides) setDotted(root, o.key, o.value_yaml);
  YAML::Emitter out;
  out << root;
  std::string text = "# written by graftnav batch: ";
  text += base_path.empty() ? "no run config" : base_path;
  for (const auto& o : overrides) text += ", " + o.key + "=" + o.value_yaml;
  return text + "\n" + out.c_str() + "\n";
}

RunConfig checkRunConfigOption(const std::string& base_path, const std::string& key,
                               const std::string& value_yaml) {
  const RunConfig base = parseBase(base_path);
  RunConfigReport report;
  const std::string source =
      "the run config " + (base_path.empty() ? std::string("(none)") : base_path) + " with it";
  RunConfig rc = applyRunConfigOverrides(base, {{key, value_yaml}}, source, &report);
  if (!report.unknown_keys.empty())
    throw std::runtime_error("unknown run-config key '" + report.unknown_keys.front() + "' (" +
                             knownKeys(report.unknown_keys.front()) + ")");
  return rc;
}

bool runConfigListsOutageWindows(const std::string& base_path) {
  return !parseBase(base_path).outages.explicit_windows.empty();
}

}  // namespace graftnav
