#pragma once
// Slurm scripts for a batch manifest: one sbatch array per command of the manifest (element I of
// command C's array runs C's tasks [I*chunk, (I+1)*chunk) through
// `graftnav batch MANIFEST --command C --task I --chunk K`), each with its own --mem, and a
// collect job that waits for all of them.
//
// Every path in the scripts is single-quoted for the shell, so a manifest or case path holding
// spaces, quotes, ';' or '$(...)' is passed through as one word and never run. Case paths do not
// appear in the scripts at all: the task reads them from the manifest. The #SBATCH lines hold
// only validated values (partition, time, memory, cpus); job logs go next to the scripts
// (sbatch is run from that folder).

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace graftnav {

struct SlurmOptions {
  std::string partition;  // empty: the cluster's default
  std::string time;       // per array element, e.g. "00:30:00" or "1-00:00:00"; empty: default
  std::string mem;        // per array element, e.g. "4G"; empty: proposed per command (below)
  int cpus = 1;           // cpus per array element (tasks of a chunk run on this many threads)
  int chunk = 1;          // tasks per array element
  // Throws std::invalid_argument naming the option and value when one would not be a plain
  // #SBATCH word (letters, digits, "_.-:" for the partition, "0-9:-" for time, N[KMGT] for mem).
  void validate() const;
};

// Single-quotes s for POSIX shells ('it'\''s').
std::string shellQuote(const std::string& s);

// The memory to ask for per array element of one command: the largest finished task's peak RSS
// with 50 % headroom, times the tasks an element runs side by side (cpus), rounded up to 64 MiB,
// at least 256 MiB. Empty without a finished task (the cluster's default then applies).
std::optional<int> proposedMemMb(std::optional<double> largest_peak_rss_mb, int cpus);

// One array: the tasks of one command.
struct SlurmArraySpec {
  std::string command;
  int task_count = 0;
  std::string mem;  // "#SBATCH --mem" value; empty: none
};

struct SlurmArray {
  SlurmArraySpec spec;
  std::string script;  // <dir>/array_<command>.sbatch
  int array_size = 0;
};

struct SlurmScripts {
  std::string dir;  // <out>/slurm
  std::vector<SlurmArray> arrays;
  std::string collect_script;  // <dir>/collect.sbatch
  std::string submit_script;   // <dir>/submit.sh: every sbatch line, the dependency wired
};

// Writes the scripts; the jobs run `graftnav_exe batch manifest_path --out out_dir ...` with all
// three paths made absolute. Throws naming the folder when it cannot be written.
SlurmScripts writeSlurmScripts(const std::string& out_dir, const std::string& graftnav_exe,
                               const std::string& manifest_path,
                               const std::vector<SlurmArraySpec>& arrays,
                               const SlurmOptions& options);

// Submits every array, then the collect job with --dependency=afterany:<every array id>, running
// sbatch from scripts.dir without a shell. Returns {array job ids, collect job id}. Throws with
// sbatch's output when it fails or is not installed.
std::pair<std::vector<std::string>, std::string> submitSlurmScripts(const SlurmScripts& scripts);

}  // namespace graftnav
