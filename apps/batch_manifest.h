#pragma once
// The manifest of `graftnav batch`, parsed in one place. Paths are relative to the manifest.
//
//   out: out/batch                  # summary.csv, summary.md and one folder per run
//   jobs: 0                         # runs in parallel; 0 = all cores
//   config: ../configs/x.yaml       # optional run config for every run (outages:, ekf:, fgo:)
//   seed: 1                         # grafting seed (or seeds: [1, 2, 3], one task per seed)
//   plots: false                    # per-run plots (default false: batch is for tables)
//   cases: [../data/sample_tactical, ../data/sample_mems]
//   estimators: [ekf, fgo]
//   outage_schedules:               # optional; default: the run config's / 60 s every 180 s
//     - {length_s: 60, period_s: 180, start_s: 300}
//
// Every task (case x estimator x schedule x seed) has a unique name, so the manifest may not hold
// two cases with the same folder name (`a/good` and `b/good`, or `good` and `good/`), nor an
// estimator, schedule or seed twice.
#include <optional>
#include <string>
#include <vector>

namespace graftnav::app {

struct OutageScheduleSpec {
  double length_s = 60.0, period_s = 180.0, start_s = 300.0;
  std::string label() const;  // e.g. "60s-every-180s-from-300s"
};

struct BatchManifest {
  std::string path;
  std::string out_dir;
  int jobs = 0;
  std::string config;
  std::vector<unsigned long long> seeds{1};
  bool plots = false;
  std::vector<std::string> cases;       // paths, relative ones resolved against the manifest
  std::vector<std::string> case_names;  // the case folders' names, unique
  std::vector<std::string> estimators{"ekf"};
  std::vector<OutageScheduleSpec> schedules;  // empty: the run config's schedule
};

// Throws std::runtime_error naming the file, line and key for a missing or malformed entry.
BatchManifest loadBatchManifest(const std::string& path);

// The folder name of a case path, ignoring a trailing '/' ("data/good/" -> "good").
std::string caseName(const std::string& case_path);

}  // namespace graftnav::app
