#include "batch_manifest.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>
#include <stdexcept>

#include "graftnav/io/yaml_fields.h"

namespace graftnav::app {
namespace fs = std::filesystem;

std::string OutageScheduleSpec::label() const {
  return fmt::format("{:g}s-every-{:g}s-from-{:g}s", length_s, period_s, start_s);
}

namespace {

namespace yf = yaml_fields;

// Throws naming the file, line and key when `value` was seen before in this list.
void requireUnique(std::set<std::string>& seen, const std::string& value, const yf::Context& ctx,
                   const YAML::Node& n, const std::string& key) {
  if (!seen.insert(value).second) {
    throw std::runtime_error(
        fmt::format("{}: '{}' lists '{}' twice; every task needs its own name and output folder",
                    yf::where(ctx, n), key, value));
  }
}

OutageScheduleSpec parseSchedule(const yf::Context& ctx, const YAML::Node& s) {
  if (!s.IsMap()) yf::fail(ctx, s, "outage_schedules", "expected a map, got " + yf::describe(s));
  OutageScheduleSpec o;
  for (const auto& f : s) {
    const std::string k = yf::asString(ctx, f.first, "outage_schedules");
    const double x = yf::asDouble(ctx, f.second, "outage_schedules." + k);
    if (k == "length_s")
      o.length_s = x;
    else if (k == "period_s")
      o.period_s = x;
    else if (k == "start_s")
      o.start_s = x;
    else
      throw std::runtime_error(yf::where(ctx, f.first) + ": unknown key 'outage_schedules." + k +
                               "'");
  }
  if (!(o.length_s > 0 && o.period_s >= o.length_s && o.start_s >= 0)) {
    throw std::runtime_error(
        yf::where(ctx, s) +
        ": outage schedule needs length_s > 0, period_s >= length_s, start_s >= 0");
  }
  return o;
}

std::vector<unsigned long long> parseSeeds(const yf::Context& ctx, const YAML::Node& v) {
  if (!v.IsSequence() || v.size() == 0) yf::fail(ctx, v, "seeds", "must be a non-empty list");
  std::vector<unsigned long long> seeds;
  std::set<std::string> seen;
  for (const auto& e : v) {
    seeds.push_back(yf::asUint64(ctx, e, "seeds"));
    requireUnique(seen, std::to_string(seeds.back()), ctx, e, "seeds");
  }
  return seeds;
}

// Case paths (resolved by `rel`) and their folder names, which must be unique.
template <typename Resolve>
void parseCases(const yf::Context& ctx, const YAML::Node& v, const Resolve& rel, BatchManifest& m) {
  if (!v.IsSequence()) yf::fail(ctx, v, "cases", "must be a list");
  std::set<std::string> seen;
  for (const auto& e : v) {
    const std::string c = rel(yf::asString(ctx, e, "cases"));
    const std::string name = caseName(c);
    if (name.empty() || name == "." || name == "..") {
      throw std::runtime_error(
          fmt::format("{}: case '{}' has no folder name", yf::where(ctx, e), c));
    }
    requireUnique(seen, name, ctx, e, "cases (folder names)");
    m.cases.push_back(c);
    m.case_names.push_back(name);
  }
}

void parseEstimators(const yf::Context& ctx, const YAML::Node& v, BatchManifest& m) {
  if (!v.IsSequence()) yf::fail(ctx, v, "estimators", "must be a list");
  m.estimators.clear();  // replaces the default
  std::set<std::string> seen;
  for (const auto& e : v) {
    m.estimators.push_back(yf::asString(ctx, e, "estimators"));
    requireUnique(seen, m.estimators.back(), ctx, e, "estimators");
  }
}

void parseSchedules(const yf::Context& ctx, const YAML::Node& v, BatchManifest& m) {
  if (!v.IsSequence()) yf::fail(ctx, v, "outage_schedules", "must be a list");
  m.schedules.clear();
  std::set<std::string> seen;
  for (const auto& e : v) {
    m.schedules.push_back(parseSchedule(ctx, e));
    requireUnique(seen, m.schedules.back().label(), ctx, e, "outage_schedules");
  }
}

}  // namespace

std::string caseName(const std::string& case_path) {
  fs::path p(case_path);
  while (!p.has_filename() && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  return p.lexically_normal().filename().string();
}

BatchManifest loadBatchManifest(const std::string& path) {
  const yf::Context ctx{path, nullptr};
  const YAML::Node root = yf::loadFile(path);
  if (root.IsDefined() && !root.IsNull() && !root.IsMap())
    throw std::runtime_error(path + ": a batch manifest must be a YAML map");
  const fs::path base = fs::path(path).parent_path();
  auto rel = [&](const std::string& p) {
    return fs::path(p).is_absolute() ? p : (base / p).lexically_normal().string();
  };
  BatchManifest m;
  m.path = path;
  bool seeds_set = false;
  for (const auto& kv : root) {
    const std::string key = yf::asString(ctx, kv.first, "(top level)");
    const YAML::Node& v = kv.second;
    if ((key == "seed" || key == "seeds") && seeds_set)
      yf::fail(ctx, kv.first, key, "give 'seed' or 'seeds', not both");
    if (key == "out") {
      m.out_dir = rel(yf::asString(ctx, v, key));
    } else if (key == "jobs") {
      m.jobs = yf::asInt(ctx, v, key);
      if (m.jobs < 0) yf::fail(ctx, v, key, "jobs must be >= 0");
    } else if (key == "config") {
      m.config = rel(yf::asString(ctx, v, key));
    } else if (key == "seed") {
      m.seeds = {yf::asUint64(ctx, v, key)};
      seeds_set = true;
    } else if (key == "seeds") {
      m.seeds = parseSeeds(ctx, v);
      seeds_set = true;
    } else if (key == "plots") {
      m.plots = yf::asBool(ctx, v, key);
    } else if (key == "cases") {
      parseCases(ctx, v, rel, m);
    } else if (key == "estimators") {
      parseEstimators(ctx, v, m);
    } else if (key == "outage_schedules") {
      parseSchedules(ctx, v, m);
    } else {
      throw std::runtime_error(yf::where(ctx, kv.first) + ": unknown key '" + key + "'");
    }
  }
  if (m.out_dir.empty()) throw std::runtime_error(path + ": missing required key 'out'");
  if (m.cases.empty())
    throw std::runtime_error(path + ": missing required key 'cases' (a non-empty list)");
  if (m.estimators.empty()) throw std::runtime_error(path + ": 'estimators' is empty");
  return m;
}

}  // namespace graftnav::app
