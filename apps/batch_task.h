#pragma once
// The tasks of a batch manifest: every case x estimator x outage schedule x seed, in a fixed
// order, each with a stable id and its own output folder.
//
// The id is a 64-bit FNV-1a hash, finalized, as 16 hex digits, over everything that decides a
// task's result: the case's name, the bytes of every file under the case folder (sorted by relative
// path, symlinks followed), the estimator, the schedule, the seed, the bytes of the run config, the
// plots switch and graftnav's version. Editing a case file or the config changes the ids of the
// tasks that use it, so a resumed batch reruns exactly those. Files a case.yaml names outside its
// own folder are not hashed.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "batch_manifest.h"

namespace graftnav::app {

struct BatchTask {
  int index = 0;   // position in the manifest's expansion order (0-based)
  std::string id;  // 16 hex digits (empty for tasks outside the range that was hashed)
  std::string case_dir;
  std::string case_name;
  std::string estimator;
  std::optional<OutageScheduleSpec> schedule;  // empty: the run config's schedule
  std::string schedule_label;                  // "config" when empty
  unsigned long long seed = 1;
  std::string name;     // "<case>__<estimator>__<schedule>__seed<N>", unique within the manifest
  std::string out_dir;  // <manifest out>/tasks/<name>
};

// graftnav's project version (the same string as provenance.h's graftnavVersion(), which only the
// executable links), part of every id.
const char* batchSoftwareVersion();

// Expands the manifest in the order cases > estimators > schedules > seeds and gives every task
// its id (expandBatchTasks) or only tasks [first, last) (an array element needs no more, and
// hashing reads every byte of the cases: a 57-minute case is ~430 MB). Each case folder is read
// once per call; throws naming the file when one cannot be read. A case folder that does not
// exist hashes as empty (its task then fails when run and records why).
std::vector<BatchTask> expandBatchTasks(const BatchManifest& manifest);
std::vector<BatchTask> expandBatchTasks(const BatchManifest& manifest, std::size_t first,
                                        std::size_t last);

// Streaming 64-bit FNV-1a, for the ids.
class Fnv1a64 {
 public:
  void add(const void* data, std::size_t size);
  void add(const std::string& s);  // the length, then the bytes (so fields cannot run together)
  std::uint64_t value() const { return h_; }
  std::string hex() const;  // finalized (see batch_task.cpp), 16 hex digits

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace graftnav::app
