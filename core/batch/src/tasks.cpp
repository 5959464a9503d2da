#include "graftnav/batch/tasks.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "graftnav/batch/task_id.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/provenance.h"

namespace graftnav {
namespace fs = std::filesystem;

const char* batchSoftwareVersion() { return graftnavVersion(); }  // graftnav/version.h

namespace {

// A YAML value as JSON: integers, numbers, booleans and null by their YAML reading, lists
// element by element, anything else as its text.
nlohmann::json yamlToJson(const YAML::Node& n) {
  if (n.IsSequence()) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : n) a.push_back(yamlToJson(e));
    return a;
  }
  if (n.IsMap()) {
    nlohmann::json o = nlohmann::json::object();
    for (const auto& kv : n) o[kv.first.Scalar()] = yamlToJson(kv.second);
    return o;
  }
  if (!n.IsScalar()) return nullptr;
  if (n.Tag() == "!") return n.Scalar();  // quoted: a string, whatever it reads like
  const std::string& s = n.Scalar();
  long long i = 0;
  double d = 0.0;
  bool b = false;
  if (YAML::convert<long long>::decode(n, i) && s.find_first_of(".eE") == std::string::npos)
    return i;
  if (YAML::convert<double>::decode(n, d)) return d;
  if (YAML::convert<bool>::decode(n, b)) return b;
  return s;
}

// A value as a folder-name part: letters, digits, '.', '+', '-' kept, anything else '_'.
std::string nameSafe(const std::string& s) {
  std::string out;
  for (unsigned char c : s)
    out += (std::isalnum(c) || c == '.' || c == '+' || c == '-') ? static_cast<char>(c) : '_';
  return out;
}

std::string joined(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

// Every combination of the option axes, the last axis fastest; one empty combination without.
std::vector<std::vector<RunConfigSetting>> optionGrid(const std::vector<OptionAxis>& axes) {
  std::vector<std::vector<RunConfigSetting>> grid{{}};
  for (const auto& a : axes) {
    std::vector<std::vector<RunConfigSetting>> next;
    for (const auto& partial : grid) {
      for (const auto& v : a.values) {
        next.push_back(partial);
        next.back().push_back({a.key, v});
      }
    }
    grid = std::move(next);
  }
  return grid;
}

// The estimator choices of a group: one task each, or one task for all (compare), or none.
std::vector<std::vector<std::string>> estimatorChoices(const BatchGroup& g) {
  const BatchCommandSpec& spec = batchCommandSpec(g.command);
  if (g.estimators.empty()) return {{}};
  if (spec.estimators_in_one_task) return {g.estimators};
  std::vector<std::vector<std::string>> out;
  for (const auto& e : g.estimators) out.push_back({e});
  return out;
}

// What every task of the group shares in its id: version, plots, command, run config, flags.
Fnv1a64 groupHash(const BatchGroup& g) {
  Fnv1a64 h;
  h.add(std::string(batchSoftwareVersion()));
  h.add(std::string(g.plots ? "plots" : "no-plots"));
  h.add(std::string(batchCommandName(g.command)));
  if (!g.run_config.empty()) addFileBytes(h, g.run_config);
  for (const auto& f : g.flags) {  // a file by its bytes, not by where it is
    h.add(f.name);
    if (f.is_file)
      addFileBytes(h, f.values.front());
    else
      for (const auto& v : f.values) h.add(v);
  }
  return h;
}

std::string taskName(const BatchTask& t) {
  std::string name = fmt::format("{}__{}__{}", t.case_name, t.estimator, t.schedule_label);
  if (t.seed) name += fmt::format("__seed{}", *t.seed);
  for (const auto& o : t.options) name += "__" + o.key + "=" + nameSafe(o.value_yaml);
  return name;
}

std::string optionsJson(const std::vector<RunConfigSetting>& options) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& o : options) j[o.key] = yamlToJson(YAML::Load(o.value_yaml));
  return j.dump();
}

// Names, folders and the order of the tasks; no file read.
struct Expansion {
  const BatchManifest& m;
  std::vector<BatchTask> tasks;
  std::map<std::string, int> folder_group;  // folder -> group that writes it

  void add(BatchTask t) {
    t.index = static_cast<int>(tasks.size());
    t.name = taskName(t);
    t.out_dir = (fs::path(m.out_dir) / "tasks" / t.grp / t.name).string();
    const auto [it, inserted] = folder_group.emplace(t.folder(), t.group);
    if (!inserted) {
      throw std::runtime_error(fmt::format(
          "{}:{}: this group and the group at line {} would both write tasks/{} (give one of "
          "them a `name:`, or drop the repeated case, estimator, schedule, seed or value)",
          m.path, m.groups[t.group].line, m.groups[it->second].line, t.folder()));
    }
    tasks.push_back(std::move(t));
  }

  void group(int gi) {
    const BatchGroup& g = m.groups[gi];
    std::vector<std::optional<OutageScheduleSpec>> schedules(g.schedules.begin(),
                                                             g.schedules.end());
    if (schedules.empty()) schedules.push_back(std::nullopt);
    std::vector<std::optional<unsigned long long>> seeds(g.seeds.begin(), g.seeds.end());
    if (seeds.empty()) seeds.push_back(std::nullopt);
    const auto grid = optionGrid(g.options);
    for (const auto& c : g.cases)
      for (const auto& est : estimatorChoices(g))
        for (const auto& values : grid)
          for (const auto& schedule : schedules)
            for (const auto& seed : seeds) {
              BatchTask t;
              t.group = gi;
              t.grp = g.name;
              t.command = g.command;
              t.case_dir = c.path;
              t.case_name = c.name;
              t.estimators = est;
              t.estimator = est.empty() ? "none" : joined(est, "+");
              t.schedule = schedule;
              t.schedule_label = schedule ? schedule->label() : "config";
              t.seed = seed;
              t.options = values;
              t.options_json = optionsJson(values);
              add(std::move(t));
            }
  }
};

std::string taskId(const Fnv1a64& group_hash, const std::string& case_hash, const BatchTask& t) {
  Fnv1a64 h = group_hash;
  h.add(t.folder());
  h.add(t.case_name);  // two identical case folders under two names are two tasks
  h.add(case_hash);
  h.add(joined(t.estimators, ","));
  // The schedule's numbers at full precision, not its rounded label.
  h.add(t.schedule ? fmt::format("{:a},{:a},{:a}", t.schedule->length_s, t.schedule->period_s,
                                 t.schedule->start_s)
                   : std::string("config"));
  h.add(t.seed ? std::to_string(*t.seed) : std::string("no seed"));
  for (const auto& o : t.options) h.add(o.key + "=" + o.value_yaml);
  return h.hex();
}

std::vector<RunConfigSetting> runConfigOverrides(const BatchTask& t) {
  std::vector<RunConfigSetting> o = t.options;
  if (t.schedule) {
    o.push_back({"outages.length_s", fmt::format("{}", t.schedule->length_s)});
    o.push_back({"outages.period_s", fmt::format("{}", t.schedule->period_s)});
    o.push_back({"outages.start_s", fmt::format("{}", t.schedule->start_s)});
  }
  return o;
}

}  // namespace

std::vector<BatchTask> expandBatchTaskList(const BatchManifest& m) {
  Expansion e{m, {}, {}};
  for (int g = 0; g < static_cast<int>(m.groups.size()); ++g) e.group(g);
  return std::move(e.tasks);
}

void assignTaskIds(const BatchManifest& m, const std::vector<std::size_t>& which,
                   std::vector<BatchTask>* tasks) {
  std::map<int, Fnv1a64> group_hash;
  std::map<std::string, std::string> case_hash;  // each case folder read once
  for (std::size_t i : which) {
    BatchTask& t = tasks->at(i);
    if (!group_hash.count(t.group)) group_hash[t.group] = groupHash(m.groups.at(t.group));
    if (!case_hash.count(t.case_dir)) case_hash[t.case_dir] = hashFolder(t.case_dir);
    t.id = taskId(group_hash[t.group], case_hash[t.case_dir], t);
  }
}

std::vector<BatchTask> expandBatchTasks(const BatchManifest& m) {
  std::vector<BatchTask> tasks = expandBatchTaskList(m);
  std::vector<std::size_t> all(tasks.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  assignTaskIds(m, all, &tasks);
  return tasks;
}

std::string taskRunConfigPath(const BatchManifest& m, const BatchTask& t) {
  if (runConfigOverrides(t).empty()) return m.groups.at(t.group).run_config;
  return (fs::path(t.out_dir) / "run_config.yaml").string();
}

void writeTaskRunConfig(const BatchManifest& m, const BatchTask& t) {
  const auto overrides = runConfigOverrides(t);
  if (overrides.empty()) return;
  fs::create_directories(t.out_dir);
  writeFileAtomically(taskRunConfigPath(m, t),
                      composeRunConfig(m.groups.at(t.group).run_config, overrides));
}

std::vector<std::string> taskCommandLine(const BatchManifest& m, const BatchTask& t,
                                         const std::string& graftnav_exe) {
  const BatchGroup& g = m.groups.at(t.group);
  const BatchCommandSpec& spec = batchCommandSpec(t.command);
  std::vector<std::string> argv{graftnav_exe, batchCommandName(t.command), t.case_dir, "--out",
                                t.out_dir};
  if (!t.estimators.empty()) {
    argv.push_back("--estimator");
    argv.push_back(joined(t.estimators, ","));
  }
  const std::string rc = taskRunConfigPath(m, t);
  if (!rc.empty()) {
    argv.push_back("--run-config");
    argv.push_back(rc);
  }
  if (t.seed) {
    argv.push_back("--seed");
    argv.push_back(std::to_string(*t.seed));
  }
  if (spec.takes_jobs) {
    argv.push_back("--jobs");
    argv.push_back("1");
  }
  if (!g.plots) argv.push_back("--no-plots");
  for (const auto& f : g.flags) {
    argv.push_back("--" + f.name);
    if (f.kind == FlagKind::kSwitch) continue;
    argv.push_back(joined(f.values, ","));
  }
  return argv;
}

}  // namespace graftnav
