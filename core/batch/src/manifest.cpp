#include "graftnav/batch/manifest.h"

#include <fmt/core.h>
#include <glob.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "graftnav/batch/run_config_overrides.h"
#include "graftnav/io/yaml_fields.h"

namespace graftnav {
namespace fs = std::filesystem;
namespace yf = yaml_fields;

std::string OutageScheduleSpec::label() const {
  return fmt::format("{:g}s-every-{:g}s-from-{:g}s", length_s, period_s, start_s);
}

namespace {

// What the parser of one group needs: the file (for messages) and the manifest's folder.
struct Where {
  yf::Context ctx;
  fs::path base;
  // Absolute: a task's command runs in the task's folder.
  std::string resolve(const std::string& p) const {
    return fs::absolute(fs::path(p).is_absolute() ? fs::path(p) : base / p)
        .lexically_normal()
        .string();
  }
  int line(const YAML::Node& n) const { return n.Mark().is_null() ? 0 : n.Mark().line + 1; }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const {
    throw std::runtime_error(yf::where(ctx, n) + ": " + what);
  }
};

// Throws naming the file, line and key when `value` was seen before in this list.
void requireUnique(std::set<std::string>& seen, const std::string& value, const Where& w,
                   const YAML::Node& n, const std::string& key) {
  if (!seen.insert(value).second)
    w.fail(n, fmt::format("'{}' lists '{}' twice; every task needs its own name and output folder",
                          key, value));
}

OutageScheduleSpec parseSchedule(const Where& w, const YAML::Node& s) {
  if (!s.IsMap()) yf::fail(w.ctx, s, "outage_schedules", "expected a map, got " + yf::describe(s));
  OutageScheduleSpec o;
  for (const auto& f : s) {
    const std::string k = yf::asString(w.ctx, f.first, "outage_schedules");
    const double x = yf::asDouble(w.ctx, f.second, "outage_schedules." + k);
    if (k == "length_s")
      o.length_s = x;
    else if (k == "period_s")
      o.period_s = x;
    else if (k == "start_s")
      o.start_s = x;
    else
      w.fail(f.first, "unknown key 'outage_schedules." + k + "' (length_s, period_s, start_s)");
  }
  if (!(o.length_s > 0 && o.period_s >= o.length_s && o.start_s >= 0))
    w.fail(s, "outage schedule needs length_s > 0, period_s >= length_s, start_s >= 0");
  return o;
}

std::vector<OutageScheduleSpec> parseSchedules(const Where& w, const YAML::Node& v) {
  if (!v.IsSequence()) yf::fail(w.ctx, v, "outage_schedules", "must be a list");
  std::vector<OutageScheduleSpec> out;
  std::set<std::string> seen;
  for (const auto& e : v) {
    out.push_back(parseSchedule(w, e));
    requireUnique(seen, out.back().label(), w, e, "outage_schedules");
  }
  return out;
}

std::vector<unsigned long long> parseSeeds(const Where& w, const YAML::Node& v) {
  if (!v.IsSequence() || v.size() == 0) yf::fail(w.ctx, v, "seeds", "must be a non-empty list");
  std::vector<unsigned long long> seeds;
  std::set<std::string> seen;
  for (const auto& e : v) {
    seeds.push_back(yf::asUint64(w.ctx, e, "seeds"));
    requireUnique(seen, std::to_string(seeds.back()), w, e, "seeds");
  }
  return seeds;
}

std::vector<std::string> parseNames(const Where& w, const YAML::Node& v, const std::string& key) {
  if (!v.IsSequence()) yf::fail(w.ctx, v, key, "must be a list");
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (const auto& e : v) {
    out.push_back(yf::asString(w.ctx, e, key));
    if (out.back().empty() || out.back().find_first_of(",/ \t") != std::string::npos)
      w.fail(e, fmt::format("'{}' entry '{}' is not a name", key, out.back()));
    requireUnique(seen, out.back(), w, e, key);
  }
  return out;
}

bool hasGlobCharacters(const std::string& p) { return p.find_first_of("*?[") != std::string::npos; }

// The folders a glob matches, sorted; a path without glob characters as it is (a folder that does
// not exist is a task that fails when it runs, and says why).
std::vector<std::string> expandCasePattern(const Where& w, const YAML::Node& e,
                                           const std::string& pattern) {
  if (!hasGlobCharacters(pattern)) return {pattern};
  glob_t g{};
  const int rc = ::glob(pattern.c_str(), GLOB_MARK, nullptr, &g);
  std::vector<std::string> out;
  for (std::size_t i = 0; rc == 0 && i < g.gl_pathc; ++i) {
    const std::string p = g.gl_pathv[i];
    if (!p.empty() && p.back() == '/') out.push_back(p.substr(0, p.size() - 1));  // folders only
  }
  globfree(&g);
  if (out.empty()) w.fail(e, fmt::format("cases: the glob '{}' matches no folder", pattern));
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<BatchCase> parseCases(const Where& w, const YAML::Node& v) {
  if (!v.IsSequence()) yf::fail(w.ctx, v, "cases", "must be a list");
  std::vector<BatchCase> out;
  std::set<std::string> seen;
  for (const auto& e : v) {
    for (const std::string& c :
         expandCasePattern(w, e, w.resolve(yf::asString(w.ctx, e, "cases")))) {
      const std::string name = caseName(c);
      if (name.empty() || name == "." || name == "..")
        w.fail(e, fmt::format("case '{}' has no folder name", c));
      requireUnique(seen, name, w, e, "cases (folder names)");
      out.push_back({c, name, w.line(e)});
    }
  }
  return out;
}

// A flag value as the command line takes it: a scalar, or for list flags a list of scalars.
std::vector<std::string> flagValues(const Where& w, const YAML::Node& v, const FlagSpec& f) {
  const std::string key = "flags." + f.name;
  if (f.kind == FlagKind::kSwitch) {
    return yf::asBool(w.ctx, v, key) ? std::vector<std::string>{"true"}
                                     : std::vector<std::string>{};
  }
  if (f.kind == FlagKind::kList && v.IsSequence()) {
    std::vector<std::string> out;
    for (const auto& e : v) out.push_back(yf::asString(w.ctx, e, key));
    if (out.empty()) yf::fail(w.ctx, v, key, "an empty list");
    return out;
  }
  const std::string s = yf::asString(w.ctx, v, key);
  if (s.empty()) yf::fail(w.ctx, v, key, "an empty value");
  return {s};
}

BatchFlag parseFlag(const Where& w, const BatchCommandSpec& spec, const YAML::Node& k,
                    const YAML::Node& v) {
  const std::string name = yf::asString(w.ctx, k, "flags");
  const FlagSpec* f = findFlag(spec, name);
  if (!f) {
    std::string known;
    for (const auto& s : spec.flags) known += (known.empty() ? "" : ", ") + s.name;
    w.fail(k, fmt::format("flags: `{}` takes no flag '{}' (it takes: {}; the batch sets --out, "
                          "--run-config, --estimator, --seed, --jobs and --no-plots itself)",
                          batchCommandName(spec.command), name, known.empty() ? "none" : known));
  }
  BatchFlag flag{name, f->kind, flagValues(w, v, *f), false, w.line(k)};
  const bool names_file =
      f->kind == FlagKind::kPath ||
      (f->kind == FlagKind::kImu && flag.values[0] != "ref" && flag.values[0] != "tested");
  if (names_file) {
    const std::string p = w.resolve(flag.values[0]);
    // An IMU file may also be relative to the case folder (the command tries there first).
    if (fs::is_regular_file(p)) {
      flag.values[0] = p;
      flag.is_file = true;
    } else if (f->kind == FlagKind::kPath) {
      w.fail(v, fmt::format("flags.{}: file '{}' not found", name, p));
    }
  }
  return flag;
}

std::vector<BatchFlag> parseFlags(const Where& w, const BatchCommandSpec& spec,
                                  const YAML::Node& v) {
  if (!v.IsMap()) yf::fail(w.ctx, v, "flags", "expected a map of flag: value");
  std::vector<BatchFlag> out;
  for (const auto& kv : v) {
    out.push_back(parseFlag(w, spec, kv.first, kv.second));
    if (out.back().kind == FlagKind::kSwitch && out.back().values.empty()) out.pop_back();
  }
  return out;
}

std::string yamlText(const YAML::Node& n) {
  if (n.IsScalar()) return n.Scalar();
  YAML::Emitter e;
  e << YAML::Flow << n;
  return e.c_str();
}

// The group's run config, or the options that set a time_range its command does not apply.
void refuseTimeRange(const Where& w, const YAML::Node& n, const TimeRangeConfig& range,
                     const std::string& source, BatchCommand command) {
  if (batchCommandSpec(command).applies_time_range) return;
  try {
    requireTimeRangeUnset(range, source, std::string("graftnav ") + batchCommandName(command));
  } catch (const std::exception& e) {
    w.fail(n, e.what());
  }
}

// Each key's values, checked against the run-config schema with the group's run config.
std::vector<OptionAxis> parseOptions(const Where& w, const YAML::Node& v,
                                     const std::string& run_config, BatchCommand command) {
  if (!v.IsMap()) yf::fail(w.ctx, v, "options", "expected a map of run-config key: [values]");
  std::vector<OptionAxis> out;
  for (const auto& kv : v) {
    OptionAxis a;
    a.key = yf::asString(w.ctx, kv.first, "options");
    a.line = w.line(kv.first);
    std::vector<YAML::Node> values;
    if (kv.second.IsSequence()) {
      for (const auto& e : kv.second) values.push_back(e);
    } else {
      values.push_back(kv.second);
    }
    if (values.empty()) w.fail(kv.second, "options." + a.key + ": an empty list of values");
    std::set<std::string> seen;
    for (const auto& e : values) {
      a.values.push_back(yamlText(e));
      a.lines.push_back(w.line(e));
      requireUnique(seen, a.values.back(), w, e, "options." + a.key);
      const YAML::Node& at = e.Mark().is_null() ? kv.first : e;
      RunConfig rc;
      try {
        rc = checkRunConfigOption(run_config, a.key, a.values.back());
      } catch (const std::exception& ex) {
        w.fail(at, fmt::format("options.{}: value '{}': {}", a.key, a.values.back(), ex.what()));
      }
      refuseTimeRange(w, at, rc.time_range,
                      (run_config.empty() ? "" : run_config + " with ") + "options." + a.key,
                      command);
    }
    out.push_back(std::move(a));
  }
  return out;
}

// The checks that need the whole group: what its command requires and allows.
void checkGroup(const Where& w, const YAML::Node& g, const BatchGroup& group, bool seeds_given) {
  const BatchCommandSpec& spec = batchCommandSpec(group.command);
  const std::string cmd = batchCommandName(group.command);
  if (group.cases.empty()) w.fail(g, "the group has no cases (a non-empty `cases` list)");
  if (seeds_given && !spec.takes_seed)
    w.fail(g["seeds"].IsDefined() ? g["seeds"] : g["seed"],
           fmt::format("`{}` takes no grafting seed (seeds apply to evaluate and real-sg)", cmd));
  if (group.estimators.empty() && !spec.estimator_optional)
    w.fail(g, fmt::format("`{}` needs at least one estimator", cmd));
  if (spec.requires_run_config && group.run_config.empty())
    w.fail(g, fmt::format("`{}` needs a run config (run_config: FILE)", cmd));
  for (const auto& r : spec.required_flags) {
    const bool given = std::any_of(group.flags.begin(), group.flags.end(),
                                   [&](const BatchFlag& f) { return f.name == r; });
    if (!given) w.fail(g, fmt::format("`{}` needs the flag '{}' (flags: {{{}: ...}})", cmd, r, r));
  }
  if (!group.schedules.empty() && runConfigListsOutageWindows(group.run_config))
    w.fail(g["outage_schedules"],
           "outage_schedules with a run config that lists outages.windows: the windows would "
           "replace every schedule");
}

BatchCommand parseCommand(const Where& w, const YAML::Node& v) {
  const std::string name = yf::asString(w.ctx, v, "command");
  const auto c = parseBatchCommand(name);
  if (!c) w.fail(v, fmt::format("unknown command '{}' (one of {})", name, batchCommandList()));
  return *c;
}

std::string parseGroupName(const Where& w, const YAML::Node& v) {
  const std::string n = yf::asString(w.ctx, v, "name");
  if (n.empty() || n == "." || n == ".." ||
      n.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") !=
          std::string::npos)
    w.fail(v, fmt::format("name '{}': letters, digits, '.', '_' and '-' only", n));
  return n;
}

// One group: `command` first (the other keys depend on it), then the rest in any order.
BatchGroup parseGroup(const Where& w, const YAML::Node& g, bool legacy) {
  if (!g.IsMap()) w.fail(g, "a group must be a map (command:, cases:, ...)");
  BatchGroup group;
  group.line = w.line(g);
  if (legacy) {
    group.command = BatchCommand::kEvaluate;
  } else if (!g["command"].IsDefined()) {
    w.fail(g, "the group has no `command` (" + batchCommandList() + ")");
  } else {
    group.command = parseCommand(w, g["command"]);
  }
  const BatchCommandSpec& spec = batchCommandSpec(group.command);
  group.name = batchCommandName(group.command);
  group.estimators = spec.default_estimators;
  if (spec.takes_seed) group.seeds = {1};
  bool seeds_given = false;
  YAML::Node options;  // parsed last: the values are checked against the run config
  bool has_options = false;
  for (const auto& kv : g) {
    const std::string key = yf::asString(w.ctx, kv.first, "(group)");
    const YAML::Node& v = kv.second;
    if ((key == "seed" || key == "seeds") && seeds_given)
      w.fail(kv.first, "give 'seed' or 'seeds', not both");
    if ((key == "config" || key == "run_config") && !group.run_config.empty())
      w.fail(kv.first, "give 'run_config' or its alias 'config', not both");
    if (key == "command" && !legacy) {
      continue;
    } else if (key == "name" && !legacy) {
      group.name = parseGroupName(w, v);
    } else if (key == "cases") {
      group.cases = parseCases(w, v);
    } else if (key == "estimators") {
      group.estimators = parseNames(w, v, key);
    } else if (key == "seed") {
      group.seeds = {yf::asUint64(w.ctx, v, key)};
      seeds_given = true;
    } else if (key == "seeds") {
      group.seeds = parseSeeds(w, v);
      seeds_given = true;
    } else if (key == "outage_schedules") {
      group.schedules = parseSchedules(w, v);
    } else if (key == "run_config" || key == "config") {
      group.run_config = w.resolve(yf::asString(w.ctx, v, key));
      if (!fs::is_regular_file(group.run_config))
        w.fail(v, fmt::format("{}: '{}' is not a file", key, group.run_config));
    } else if (key == "flags" && !legacy) {
      group.flags = parseFlags(w, spec, v);
    } else if (key == "options") {
      options.reset(kv.second);
      has_options = true;
    } else if (key == "plots") {
      group.plots = yf::asBool(w.ctx, v, key);
    } else if (!legacy || (key != "out" && key != "jobs")) {
      w.fail(kv.first, fmt::format("unknown key '{}'{}", key,
                                   legacy ? ""
                                          : " in a group (command, name, cases, estimators, "
                                            "seeds, outage_schedules, run_config, flags, "
                                            "options, plots)"));
    }
  }
  if (!group.run_config.empty())
    refuseTimeRange(w, g["run_config"].IsDefined() ? g["run_config"] : g["config"],
                    loadRunConfig(group.run_config).time_range, group.run_config, group.command);
  if (has_options) group.options = parseOptions(w, options, group.run_config, group.command);
  checkGroup(w, g, group, seeds_given);
  return group;
}

}  // namespace

std::string caseName(const std::string& case_path) {
  fs::path p(case_path);
  while (!p.has_filename() && p.has_parent_path() && p != p.parent_path()) p = p.parent_path();
  return p.lexically_normal().filename().string();
}

BatchManifest loadBatchManifest(const std::string& path) {
  Where w;
  w.ctx.path = path;
  w.base = fs::path(path).parent_path();
  const YAML::Node root = yf::loadFile(path);
  if (!root.IsMap()) throw std::runtime_error(path + ": a batch manifest must be a YAML map");
  BatchManifest m;
  m.path = path;
  for (const auto& kv : root) {
    const std::string key = yf::asString(w.ctx, kv.first, "(top level)");
    if (key == "out") {
      m.out_dir = w.resolve(yf::asString(w.ctx, kv.second, key));
    } else if (key == "jobs") {
      m.jobs = yf::asInt(w.ctx, kv.second, key);
      if (m.jobs < 0) yf::fail(w.ctx, kv.second, key, "jobs must be >= 0");
    }
  }
  if (m.out_dir.empty()) throw std::runtime_error(path + ": missing required key 'out'");
  const YAML::Node groups = root["groups"];
  if (!groups.IsDefined()) {  // the earlier layout: one evaluate group at the top level
    m.groups.push_back(parseGroup(w, root, true));
    return m;
  }
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (key != "out" && key != "jobs" && key != "groups")
      w.fail(kv.first, fmt::format("unknown top-level key '{}' (out, jobs, groups; a group's keys "
                                   "go inside its entry of `groups`)",
                                   key));
  }
  if (!groups.IsSequence() || groups.size() == 0)
    w.fail(groups, "'groups' must be a non-empty list");
  for (const auto& g : groups) m.groups.push_back(parseGroup(w, g, false));
  return m;
}

}  // namespace graftnav
