#pragma once
// Slurm scripts for a batch manifest: an sbatch array (element I runs tasks [I*chunk, (I+1)*chunk)
// through `graftnav batch MANIFEST --task I --chunk K`) and a collect job that depends on it.
//
// Every path in the scripts is single-quoted for the shell, so a manifest or case path holding
// spaces, quotes, ';' or '$(...)' is passed through as one word and never run. Case paths do not
// appear in the scripts at all: the task reads them from the manifest. The #SBATCH lines hold
// only validated values (partition, time, memory, cpus); job logs go next to the scripts
// (sbatch is run from that folder).
#include <string>
#include <vector>

namespace graftnav::app {

struct SlurmOptions {
  std::string partition;  // empty: the cluster's default
  std::string time;       // per array element, e.g. "00:30:00" or "1-00:00:00"; empty: default
  std::string mem;        // per array element, e.g. "4G"; empty: default
  int cpus = 1;           // cpus per array element (tasks of a chunk run on this many threads)
  int chunk = 1;          // tasks per array element
  // Throws std::invalid_argument naming the option and value when one would not be a plain
  // #SBATCH word (letters, digits, "_.-:" for the partition, "0-9:-" for time, N[KMGT] for mem).
  void validate() const;
};

// Single-quotes s for POSIX shells ('it'\''s').
std::string shellQuote(const std::string& s);

struct SlurmScripts {
  std::string dir;             // <out>/slurm
  std::string array_script;    // <dir>/array.sbatch
  std::string collect_script;  // <dir>/collect.sbatch
  std::string submit_script;   // <dir>/submit.sh: both sbatch lines, the dependency wired
  int array_size = 0;
};

// Writes the three scripts for `task_count` tasks; the jobs run
//   graftnav_exe batch manifest_path --out out_dir ...
// with all three paths made absolute. Throws naming the folder when it cannot be written.
SlurmScripts writeSlurmScripts(const std::string& out_dir, const std::string& graftnav_exe,
                               const std::string& manifest_path, int task_count,
                               const SlurmOptions& options);

// Submits the array, then the collect job with --dependency=afterany:<array id>, running sbatch
// from scripts.dir without a shell. Returns {array job id, collect job id}. Throws with sbatch's
// output when it fails or is not installed.
std::pair<std::string, std::string> submitSlurmScripts(const SlurmScripts& scripts);

// Runs argv (no shell) in cwd, returns {exit status, stdout+stderr}. argv[0] is looked up in PATH.
std::pair<int, std::string> runProgram(const std::vector<std::string>& argv,
                                       const std::string& cwd);

}  // namespace graftnav::app
