#include "graftnav/batch/slurm.h"

#include <fmt/core.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "graftnav/batch/child_process.h"
#include "graftnav/io/atomic_file.h"

namespace graftnav {
namespace fs = std::filesystem;
namespace {

bool allOf(const std::string& s, const std::string& extra, bool digits_only) {
  for (unsigned char c : s) {
    const bool ok = digits_only ? std::isdigit(c) : std::isalnum(c);
    if (!ok && extra.find(static_cast<char>(c)) == std::string::npos) return false;
  }
  return true;
}

void writeScript(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text);
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
}

std::string arrayScript(const SlurmArray& a, const std::string& command, const SlurmOptions& o,
                        const std::string& common) {
  std::string s = fmt::format(
      "#!/bin/bash\n# graftnav batch: the {} tasks, one array element per chunk (written by "
      "--slurm).\n",
      a.spec.command);
  s += fmt::format(
      "#SBATCH --job-name=graftnav-{}\n#SBATCH --array=0-{}\n#SBATCH --cpus-per-task={}\n",
      a.spec.command, a.array_size - 1, o.cpus);
  s += "#SBATCH --output=slurm-batch-%A_%a.out\n" + common;  // %A: each array has its own id
  if (!o.time.empty()) s += "#SBATCH --time=" + o.time + "\n";
  if (!a.spec.mem.empty()) s += "#SBATCH --mem=" + a.spec.mem + "\n";
  s += fmt::format(
      "set -euo pipefail\nexec {} --command {} --task \"$SLURM_ARRAY_TASK_ID\" --chunk {} "
      "--jobs {}\n",
      command, a.spec.command, o.chunk, o.cpus);
  return s;
}

std::string submitScript(const SlurmScripts& s) {
  std::string t =
      "#!/bin/bash\n# Submits every array and the collect job that waits for them.\nset -euo "
      "pipefail\n";
  t += "cd " + shellQuote(s.dir) + "\nids=\n";
  for (const auto& a : s.arrays) {
    t += fmt::format("id=$(sbatch --parsable {})\nids=\"$ids:${{id%%;*}}\"\n",
                     fs::path(a.script).filename().string());
  }
  t += "collect_id=$(sbatch --parsable --dependency=afterany\"$ids\" collect.sbatch)\n";
  t += "echo \"array jobs ${ids#:}, collect job ${collect_id%%;*}\"\n";
  return t;
}

}  // namespace

void SlurmOptions::validate() const {
  auto bad = [](const std::string& opt, const std::string& v, const std::string& want) {
    return std::invalid_argument(fmt::format("--{} '{}' is not a Slurm value ({})", opt, v, want));
  };
  if (!allOf(partition, "_.-,", false))
    throw bad("partition", partition, "letters, digits, '_', '.', '-', ','");
  if (!allOf(time, ":-", true)) throw bad("time", time, "e.g. 30, 01:00:00 or 1-00:00:00");
  if (!mem.empty()) {
    const bool unit = std::string("KMGT").find(mem.back()) != std::string::npos;
    const std::string digits = unit ? mem.substr(0, mem.size() - 1) : mem;
    if (digits.empty() || !allOf(digits, "", true)) throw bad("mem", mem, "e.g. 4000 or 4G");
  }
  if (cpus < 1) throw bad("cpus", std::to_string(cpus), ">= 1");
  if (chunk < 1) throw bad("chunk", std::to_string(chunk), ">= 1");
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::optional<int> proposedMemMb(std::optional<double> largest_peak_rss_mb, int cpus) {
  if (!largest_peak_rss_mb || !(*largest_peak_rss_mb > 0.0)) return std::nullopt;
  const double mb = 1.5 * *largest_peak_rss_mb * std::max(1, cpus);
  return std::max(256, 64 * static_cast<int>(std::ceil(mb / 64.0)));
}

SlurmScripts writeSlurmScripts(const std::string& out_dir, const std::string& graftnav_exe,
                               const std::string& manifest_path,
                               const std::vector<SlurmArraySpec>& arrays, const SlurmOptions& o) {
  o.validate();
  SlurmScripts s;
  const std::string out = fs::absolute(out_dir).lexically_normal().string();
  s.dir = (fs::path(out) / "slurm").string();
  fs::create_directories(s.dir);
  std::string common;
  if (!o.partition.empty()) common += "#SBATCH --partition=" + o.partition + "\n";
  const std::string command = fmt::format(
      "{} batch {} --out {}", shellQuote(fs::absolute(graftnav_exe).string()),
      shellQuote(fs::absolute(manifest_path).lexically_normal().string()), shellQuote(out));
  for (const auto& spec : arrays) {
    if (spec.task_count < 1) continue;
    SlurmArray a{spec, (fs::path(s.dir) / ("array_" + spec.command + ".sbatch")).string(),
                 (spec.task_count + o.chunk - 1) / o.chunk};
    if (!o.mem.empty()) a.spec.mem = o.mem;
    writeScript(a.script, arrayScript(a, command, o, common));
    s.arrays.push_back(a);
  }
  if (s.arrays.empty())
    throw std::invalid_argument("the manifest expands to no task: nothing to submit");
  s.collect_script = (fs::path(s.dir) / "collect.sbatch").string();
  s.submit_script = (fs::path(s.dir) / "submit.sh").string();
  std::string collect =
      "#!/bin/bash\n# graftnav batch: merge the task results once the arrays are over.\n";
  collect +=
      "#SBATCH --job-name=graftnav-collect\n#SBATCH --cpus-per-task=1\n#SBATCH "
      "--output=slurm-collect-%j.out\n";
  collect += common + "set -euo pipefail\nexec " + command + " --collect\n";
  writeScript(s.collect_script, collect);
  writeScript(s.submit_script, submitScript(s));
  return s;
}

std::pair<std::vector<std::string>, std::string> submitSlurmScripts(const SlurmScripts& s) {
  auto sbatch = [&](std::vector<std::string> argv) {
    const auto [rc, out] = runProgram(argv, s.dir);
    if (rc != 0) {
      throw std::runtime_error(fmt::format("'{}' in '{}' failed (exit {}{}): {}",
                                           argv.front() + " ... " + argv.back(), s.dir, rc,
                                           rc == 127 ? ", sbatch not found" : "", out));
    }
    std::string id = out.substr(0, out.find_first_of(";\n"));
    if (id.empty() || !allOf(id, "", true))
      throw std::runtime_error("sbatch printed no job id: " + out);
    return id;
  };
  std::vector<std::string> ids;
  std::string dependency = "--dependency=afterany";
  for (const auto& a : s.arrays) {
    ids.push_back(sbatch({"sbatch", "--parsable", fs::path(a.script).filename().string()}));
    dependency += ":" + ids.back();
  }
  const std::string collect_id = sbatch({"sbatch", "--parsable", dependency, "collect.sbatch"});
  return {ids, collect_id};
}

}  // namespace graftnav
