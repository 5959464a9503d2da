#include "batch_slurm.h"

#include <fcntl.h>
#include <fmt/core.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"

namespace graftnav::app {
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

SlurmScripts writeSlurmScripts(const std::string& out_dir, const std::string& graftnav_exe,
                               const std::string& manifest_path, int task_count,
                               const SlurmOptions& o) {
  o.validate();
  if (task_count < 1)
    throw std::invalid_argument("the manifest expands to no task: nothing to submit");
  SlurmScripts s;
  const std::string out = fs::absolute(out_dir).lexically_normal().string();
  s.dir = (fs::path(out) / "slurm").string();
  fs::create_directories(s.dir);
  s.array_script = (fs::path(s.dir) / "array.sbatch").string();
  s.collect_script = (fs::path(s.dir) / "collect.sbatch").string();
  s.submit_script = (fs::path(s.dir) / "submit.sh").string();
  s.array_size = (task_count + o.chunk - 1) / o.chunk;

  std::string common;
  if (!o.partition.empty()) common += "#SBATCH --partition=" + o.partition + "\n";
  const std::string command = fmt::format(
      "{} batch {} --out {}", shellQuote(fs::absolute(graftnav_exe).string()),
      shellQuote(fs::absolute(manifest_path).lexically_normal().string()), shellQuote(out));
  std::string array =
      "#!/bin/bash\n# graftnav batch: one array element per chunk of tasks (written by --slurm).\n";
  array += fmt::format(
      "#SBATCH --job-name=graftnav-batch\n#SBATCH --array=0-{}\n#SBATCH --cpus-per-task={}\n",
      s.array_size - 1, o.cpus);
  array += "#SBATCH --output=slurm-batch-%A_%a.out\n" + common;
  if (!o.time.empty()) array += "#SBATCH --time=" + o.time + "\n";
  if (!o.mem.empty()) array += "#SBATCH --mem=" + o.mem + "\n";
  array += fmt::format(
      "set -euo pipefail\nexec {} --task \"$SLURM_ARRAY_TASK_ID\" --chunk {} --jobs {}\n", command,
      o.chunk, o.cpus);
  writeScript(s.array_script, array);

  std::string collect =
      "#!/bin/bash\n# graftnav batch: merge the task results once the array is over.\n";
  collect +=
      "#SBATCH --job-name=graftnav-collect\n#SBATCH --cpus-per-task=1\n#SBATCH "
      "--output=slurm-collect-%j.out\n";
  collect += common + "set -euo pipefail\nexec " + command + " --collect\n";
  writeScript(s.collect_script, collect);

  std::string submit =
      "#!/bin/bash\n# Submits the array and the collect job that waits for it.\nset -euo "
      "pipefail\n";
  submit += "cd " + shellQuote(s.dir) + "\n";
  submit += "array_id=$(sbatch --parsable array.sbatch)\narray_id=${array_id%%;*}\n";
  submit += "collect_id=$(sbatch --parsable --dependency=afterany:\"$array_id\" collect.sbatch)\n";
  submit += "echo \"array job $array_id, collect job ${collect_id%%;*}\"\n";
  writeScript(s.submit_script, submit);
  return s;
}

std::pair<int, std::string> runProgram(const std::vector<std::string>& argv,
                                       const std::string& cwd) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe() failed");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork() failed");
  if (pid == 0) {
    ::dup2(fds[1], STDOUT_FILENO);
    ::dup2(fds[1], STDERR_FILENO);
    ::close(fds[0]);
    ::close(fds[1]);
    if (::chdir(cwd.c_str()) != 0) ::_exit(126);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  std::string output;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;)
    output.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, output};
}

std::pair<std::string, std::string> submitSlurmScripts(const SlurmScripts& s) {
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
  const std::string array_id = sbatch({"sbatch", "--parsable", "array.sbatch"});
  const std::string collect_id =
      sbatch({"sbatch", "--parsable", "--dependency=afterany:" + array_id, "collect.sbatch"});
  return {array_id, collect_id};
}

}  // namespace graftnav::app
