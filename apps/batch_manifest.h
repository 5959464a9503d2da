#pragma once
// The manifest of `graftnav batch`, parsed in one place. Paths are relative to the manifest.
//
//   out: out/batch                  # summary.csv, summary.md and one folder per run
//   jobs: 0                         # runs in parallel; 0 = all cores
//   config: ../configs/x.yaml       # optional run config for every run (outages:, ekf:, fgo:)
//   seed: 1                         # grafting seed
//   plots: false                    # per-run plots (default false: batch is for tables)
//   cases: [../data/sample_tactical, ../data/sample_mems]
//   estimators: [ekf, fgo]
//   outage_schedules:               # optional; default: the run config's / 60 s every 180 s
//     - {length_s: 60, period_s: 180, start_s: 300}
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
  unsigned long long seed = 1;
  bool plots = false;
  std::vector<std::string> cases;
  std::vector<std::string> estimators{"ekf"};
  std::vector<OutageScheduleSpec> schedules;  // empty: the run config's schedule
};

// Throws std::runtime_error naming the file, line and key for a missing or malformed entry.
BatchManifest loadBatchManifest(const std::string& path);

}  // namespace graftnav::app
