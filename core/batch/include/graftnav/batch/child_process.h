#pragma once
// A task's command as a child process: argv passed as a vector (no shell), its stdout and stderr
// into files, and what the kernel measured of it (wait4's rusage): peak resident memory and CPU
// time. A crash or a non-zero exit is the child's own; the caller decides what it means.

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace graftnav {

struct ChildResult {
  int exit_code = -1;  // when it exited (-1 when a signal ended it)
  int signal = 0;      // the signal that ended it, 0 when it exited
  double peak_rss_mb = std::numeric_limits<double>::quiet_NaN();  // ru_maxrss, MiB
  double cpu_seconds = 0.0;                                       // user + system time
  double wall_seconds = 0.0;                                      // start to end
  bool ok() const { return signal == 0 && exit_code == 0; }
  // "exit code 1" or "killed by signal 11 (Segmentation fault)".
  std::string describe() const;
};

// Runs argv[0] (a path, not looked up in PATH) with its arguments in folder `cwd`, stdout and
// stderr written to the two files (created or truncated), and waits for it. The child is killed
// (SIGKILL) if the thread that started it dies, so a killed batch leaves no task running. Throws
// std::runtime_error only when no process could be started at all; a program that cannot be
// executed exits with code 127 and says why in its stderr file.
ChildResult runChildProcess(const std::vector<std::string>& argv, const std::string& cwd,
                            const std::string& stdout_path, const std::string& stderr_path);

// Runs argv (argv[0] looked up in PATH, no shell) in cwd; returns {exit status, stdout+stderr}
// (status 127: it could not be run, 128: a signal ended it).
std::pair<int, std::string> runProgram(const std::vector<std::string>& argv,
                                       const std::string& cwd);

// The last `n` non-empty lines of a text file (fewer when it has fewer), joined by "\n".
std::string lastLines(const std::string& path, int n);

}  // namespace graftnav
