#include "graftnav/batch/run_config_overrides.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "graftnav/io/yaml_fields.h"

namespace graftnav {
namespace {

std::vector<std::string> splitKey(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string p;
  while (std::getline(ss, p, '.')) parts.push_back(p);
  if (parts.size() < 2 ||
      std::any_of(parts.begin(), parts.end(), [](const std::string& s) { return s.empty(); }))
    throw std::runtime_error("'" + key + "' is not a dotted run-config key (section.key)");
  return parts;
}

YAML::Node loadBase(const std::string& base_path) {
  if (base_path.empty()) return YAML::Node(YAML::NodeType::Map);
  YAML::Node root = yaml_fields::loadFile(base_path);
  if (!root.IsDefined() || root.IsNull()) return YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw std::runtime_error(base_path + ": the run config must be a YAML map");
  return root;
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
  cur[parts.back()] = YAML::Load(value_yaml);
}

}  // namespace

std::string composeRunConfig(const std::string& base_path,
                             const std::vector<RunConfigOverride>& overrides) {
  YAML::Node root = YAML::Clone(loadBase(base_path));
  for (const auto& o : overrides) setDotted(root, o.key, o.value_yaml);
  YAML::Emitter out;
  out << root;
  std::string text = "# written by graftnav batch: ";
  text += base_path.empty() ? "no run config" : base_path;
  for (const auto& o : overrides) text += ", " + o.key + "=" + o.value_yaml;
  return text + "\n" + out.c_str() + "\n";
}

void checkRunConfigOption(const std::string& base_path, const std::string& key,
                          const std::string& value_yaml) {
  static const char* const kSections[] = {"time_range", "outages", "ekf",     "evaluation",
                                          "fgo",        "gnss",    "grafting"};
  const std::vector<std::string> parts = splitKey(key);
  if (std::find(std::begin(kSections), std::end(kSections), parts.front()) == std::end(kSections))
    throw std::runtime_error("unknown run-config section '" + parts.front() + "'");
  YAML::Node root = YAML::Clone(loadBase(base_path));
  setDotted(root, key, value_yaml);
}

bool runConfigListsOutageWindows(const std::string& base_path) {
  const YAML::Node root = loadBase(base_path);
  const YAML::Node o = root["outages"];
  return o.IsDefined() && o.IsMap() && o["windows"].IsDefined();
}

}  // namespace graftnav
