#include "batch_manifest.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>
#include <stdexcept>

namespace graftnav::app {
namespace fs = std::filesystem;

std::string OutageScheduleSpec::label() const {
  return fmt::format("{:g}s-every-{:g}s-from-{:g}s", length_s, period_s, start_s);
}

namespace {

std::string where(const std::string& file, const YAML::Node& n) {
  return fmt::format("{}:{}", file, n.Mark().line + 1);
}

template <typename T>
T get(const std::string& file, const YAML::Node& n, const std::string& key) {
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(
        fmt::format("{}: key '{}' has a value of the wrong type", where(file, n), key));
  }
}

std::vector<std::string> stringList(const std::string& file, const YAML::Node& n,
                                    const std::string& key) {
  if (!n.IsSequence())
    throw std::runtime_error(fmt::format("{}: '{}' must be a list", where(file, n), key));
  std::vector<std::string> v;
  for (const auto& e : n) v.push_back(get<std::string>(file, e, key));
  return v;
}

// Throws naming the file, line and key when `value` was seen before in this list.
void requireUnique(std::set<std::string>& seen, const std::string& value, const std::string& file,
                   const YAML::Node& n, const std::string& key) {
  if (!seen.insert(value).second) {
    throw std::runtime_error(
        fmt::format("{}: '{}' lists '{}' twice; every task needs its own name and output folder",
                    where(file, n), key, value));
  }
}

OutageScheduleSpec parseSchedule(const std::string& path, const YAML::Node& s) {
  OutageScheduleSpec o;
  for (const auto& f : s) {
    const std::string k = f.first.as<std::string>();
    const double x = get<double>(path, f.second, "outage_schedules." + k);
    if (k == "length_s")
      o.length_s = x;
    else if (k == "period_s")
      o.period_s = x;
    else if (k == "start_s")
      o.start_s = x;
    else
      throw std::runtime_error(where(path, f.first) + ": unknown key 'outage_schedules." + k + "'");
  }
  if (!(o.length_s > 0 && o.period_s >= o.length_s && o.start_s >= 0)) {
    throw std::runtime_error(
        where(path, s) +
        ": outage schedule needs length_s > 0, period_s >= length_s, start_s >= 0");
  }
  return o;
}

std::vector<unsigned long long> parseSeeds(const std::string& path, const YAML::Node& v) {
  if (!v.IsSequence() || v.size() == 0)
    throw std::runtime_error(where(path, v) + ": 'seeds' must be a non-empty list");
  std::vector<unsigned long long> seeds;
  std::set<std::string> seen;
  for (const auto& e : v) {
    seeds.push_back(get<unsigned long long>(path, e, "seeds"));
    requireUnique(seen, std::to_string(seeds.back()), path, e, "seeds");
  }
  return seeds;
}

// Case paths (resolved by `rel`) and their folder names, which must be unique.
template <typename Resolve>
void parseCases(const std::string& path, const YAML::Node& v, const Resolve& rel,
                BatchManifest& m) {
  if (!v.IsSequence())
    throw std::runtime_error(fmt::format("{}: 'cases' must be a list", where(path, v)));
  std::set<std::string> seen;
  for (const auto& e : v) {
    const std::string c = rel(get<std::string>(path, e, "cases"));
    const std::string name = caseName(c);
    if (name.empty() || name == "." || name == "..") {
      throw std::runtime_error(fmt::format("{}: case '{}' has no folder name", where(path, e), c));
    }
    requireUnique(seen, name, path, e, "cases (folder names)");
    m.cases.push_back(c);
    m.case_names.push_back(name);
  }
}

}  // namespace

std::string caseName(const std::string& case_path) {
  fs::path p(case_path);
  while (!p.has_filename() && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  return p.lexically_normal().filename().string();
}

BatchManifest loadBatchManifest(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error("batch manifest '" + path + "' cannot be read");
  } catch (const YAML::ParserException& e) {
    throw std::runtime_error(
        fmt::format("{}:{}: YAML syntax error: {}", path, e.mark.line + 1, e.msg));
  }
  const fs::path base = fs::path(path).parent_path();
  auto rel = [&](const std::string& p) {
    return fs::path(p).is_absolute() ? p : (base / p).lexically_normal().string();
  };
  BatchManifest m;
  m.path = path;
  bool seeds_set = false;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const YAML::Node& v = kv.second;
    if (key == "out") {
      m.out_dir = rel(get<std::string>(path, v, key));
    } else if (key == "jobs") {
      m.jobs = get<int>(path, v, key);
      if (m.jobs < 0) throw std::runtime_error(where(path, v) + ": jobs must be >= 0");
    } else if (key == "config") {
      m.config = rel(get<std::string>(path, v, key));
    } else if (key == "seed") {
      if (seeds_set)
        throw std::runtime_error(where(path, kv.first) + ": give 'seed' or 'seeds', not both");
      m.seeds = {get<unsigned long long>(path, v, key)};
      seeds_set = true;
    } else if (key == "seeds") {
      if (seeds_set)
        throw std::runtime_error(where(path, kv.first) + ": give 'seed' or 'seeds', not both");
      m.seeds = parseSeeds(path, v);
      seeds_set = true;
    } else if (key == "plots") {
      m.plots = get<bool>(path, v, key);
    } else if (key == "cases") {
      parseCases(path, v, rel, m);
    } else if (key == "estimators") {
      m.estimators = stringList(path, v, key);
      std::set<std::string> seen;
      for (std::size_t i = 0; i < m.estimators.size(); ++i)
        requireUnique(seen, m.estimators[i], path, v[i], key);
    } else if (key == "outage_schedules") {
      if (!v.IsSequence())
        throw std::runtime_error(where(path, v) + ": 'outage_schedules' must be a list");
      std::set<std::string> seen;
      for (const auto& e : v) {
        m.schedules.push_back(parseSchedule(path, e));
        requireUnique(seen, m.schedules.back().label(), path, e, key);
      }
    } else {
      throw std::runtime_error(where(path, kv.first) + ": unknown key '" + key + "'");
    }
  }
  if (m.out_dir.empty()) throw std::runtime_error(path + ": missing required key 'out'");
  if (m.cases.empty())
    throw std::runtime_error(path + ": missing required key 'cases' (a non-empty list)");
  if (m.estimators.empty()) throw std::runtime_error(path + ": 'estimators' is empty");
  return m;
}

}  // namespace graftnav::app
