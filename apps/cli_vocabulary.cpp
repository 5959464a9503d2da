#include "cli_vocabulary.h"

#include <fmt/core.h>

#include <filesystem>
#include <stdexcept>

#include "graftnav/case/case_inputs.h"

namespace graftnav::app {

namespace fs = std::filesystem;

std::string imuChoice(const std::string& given, const std::string& case_dir) {
  std::string note;
  const std::string which = chooseImu(given, CasePaths(case_dir), &note);
  if (!note.empty()) fmt::print(stderr, "note: {}\n", note);
  return which;
}

std::vector<std::string> splitEstimatorList(const std::string& list) {
  std::vector<std::string> out;
  size_t begin = 0;
  while (begin <= list.size()) {
    const size_t end = std::min(list.find(',', begin), list.size());
    std::string name = list.substr(begin, end - begin);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name.empty())
      throw std::invalid_argument("--estimator '" + list + "': empty name in the list");
    out.push_back(name);
    begin = end + 1;
  }
  return out;
}

void addDeprecatedOption(CLI::App* cmd, const std::string& old_name, const std::string& new_name,
                         std::string* target) {
  cmd->add_option_function<std::string>(
         old_name,
         [=](const std::string& v) {
           fmt::print(stderr, "warning: {} is deprecated, use {}\n", old_name, new_name);
           *target = v;
         },
         "deprecated: use " + new_name)
      ->group("");
}

void addDeprecatedOption(CLI::App* cmd, const std::string& old_name, const std::string& new_name,
                         std::vector<std::string>* target) {
  cmd->add_option_function<std::string>(
         old_name,
         [=](const std::string& v) {
           fmt::print(stderr, "warning: {} is deprecated, use {}\n", old_name, new_name);
           *target = splitEstimatorList(v);
         },
         "deprecated: use " + new_name)
      ->group("");
}

void requireValue(const std::string& value, const std::string& flag) {
  if (value.empty()) throw CLI::RequiredError(flag);
}

void addDeprecatedFlag(CLI::App* cmd, const std::string& old_name, const std::string& new_name,
                       bool* target) {
  cmd->add_flag_function(
         old_name,
         [=](std::int64_t) {
           fmt::print(stderr, "warning: {} is deprecated, use {}\n", old_name, new_name);
           *target = true;
         },
         "deprecated: use " + new_name)
      ->group("");
}

void addTimeRangeOptions(CLI::App* cmd, TimeRangeConfig* range) {
  cmd->add_option_function<double>(
      "--start", [range](double t) { range->start_s = t; },
      "navigate from this time (GNSS s of week; default: run config time_range, else the data start)");
  cmd->add_option_function<double>(
      "--end", [range](double t) { range->end_s = t; },
      "navigate up to this time (GNSS s of week; default: run config time_range, else the data end)");
}

std::string resolveUserPath(const std::string& path, const std::string& case_dir,
                            const std::string& what) {
  std::vector<fs::path> tried;
  if (fs::path(path).is_absolute() || case_dir.empty()) {
    tried.push_back(path);
  } else {
    tried.push_back(fs::path(case_dir) / path);
    tried.push_back(path);
  }
  for (const auto& p : tried)
    if (fs::exists(p)) return p.string();
  std::string list;
  for (const auto& p : tried)
    list += (list.empty() ? "'" : ", '") + fs::absolute(p).lexically_normal().string() + "'";
  throw std::runtime_error(what + " '" + path + "' not found; tried " + list);
}

std::string runConfigPathFor(const std::string& given, const std::string& case_dir) {
  if (!given.empty()) return resolveUserPath(given, case_dir, "run config");
  const fs::path own = fs::path(case_dir) / "run.yaml";
  return fs::is_regular_file(own) ? own.string() : std::string();
}

}  // namespace graftnav::app
