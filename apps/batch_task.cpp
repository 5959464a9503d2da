#include "batch_task.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

namespace graftnav::app {
namespace fs = std::filesystem;

#ifndef GRAFTNAV_VERSION
#error "GRAFTNAV_VERSION must be defined by the build (apps/CMakeLists.txt)"
#endif
const char* batchSoftwareVersion() { return GRAFTNAV_VERSION; }

void Fnv1a64::add(const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h_ ^= p[i];
    h_ *= 0x100000001b3ULL;
  }
}

void Fnv1a64::add(const std::string& s) {
  const std::uint64_t n = s.size();
  add(&n, sizeof n);
  add(s.data(), s.size());
}

// FNV-1a mixes its last bytes weakly (ids of seed 1 and seed 2 would share most digits); a
// 64-bit finalizer (xor-shift-multiply, the constants of MurmurHash3's fmix64) spreads them.
std::string Fnv1a64::hex() const {
  std::uint64_t x = h_;
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return fmt::format("{:016x}", x);
}

namespace {

void addFileBytes(Fnv1a64& h, const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("batch: cannot read '" + file.string() + "' to hash it");
  const std::uint64_t size = fs::file_size(file);
  h.add(&size, sizeof size);
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    h.add(buf, static_cast<std::size_t>(in.gcount()));
  }
}

// Hash of every regular file under dir: relative path and bytes, in sorted path order.
std::string hashFolder(const std::string& dir) {
  Fnv1a64 h;
  if (!fs::is_directory(dir)) return h.hex();
  std::vector<fs::path> files;
  for (const auto& e :
       fs::recursive_directory_iterator(dir, fs::directory_options::follow_directory_symlink)) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    h.add(f.lexically_relative(dir).generic_string());
    addFileBytes(h, f);
  }
  return h.hex();
}

}  // namespace

std::vector<BatchTask> expandBatchTasks(const BatchManifest& m) {
  return expandBatchTasks(m, 0, std::numeric_limits<std::size_t>::max());
}

std::vector<BatchTask> expandBatchTasks(const BatchManifest& m, std::size_t first,
                                        std::size_t last) {
  Fnv1a64 options;
  options.add(std::string(batchSoftwareVersion()));
  options.add(std::string(m.plots ? "plots" : "no-plots"));
  if (!m.config.empty()) {
    if (!fs::is_regular_file(m.config))
      throw std::runtime_error(m.path + ": config '" + m.config + "' is not a file");
    addFileBytes(options, m.config);
  }
  std::vector<std::optional<OutageScheduleSpec>> schedules(m.schedules.begin(), m.schedules.end());
  if (schedules.empty()) schedules.push_back(std::nullopt);

  std::vector<BatchTask> tasks;
  for (std::size_t c = 0; c < m.cases.size(); ++c) {
    std::optional<std::string> case_hash;  // read when the first task of this case needs it
    for (const auto& estimator : m.estimators) {
      for (const auto& schedule : schedules) {
        for (const auto seed : m.seeds) {
          BatchTask t;
          t.index = static_cast<int>(tasks.size());
          t.case_dir = m.cases[c];
          t.case_name = m.case_names[c];
          t.estimator = estimator;
          t.schedule = schedule;
          t.schedule_label = schedule ? schedule->label() : "config";
          t.seed = seed;
          t.name =
              fmt::format("{}__{}__{}__seed{}", t.case_name, estimator, t.schedule_label, seed);
          t.out_dir = (fs::path(m.out_dir) / "tasks" / t.name).string();
          if (tasks.size() >= first && tasks.size() < last) {
            if (!case_hash) case_hash = hashFolder(m.cases[c]);
            Fnv1a64 h = options;
            h.add(t.case_name);  // two identical case folders under two names are two tasks
            h.add(*case_hash);
            h.add(estimator);
            // The schedule's numbers at full precision, not its rounded label.
            h.add(schedule ? fmt::format("{:a},{:a},{:a}", schedule->length_s, schedule->period_s,
                                         schedule->start_s)
                           : std::string("config"));
            h.add(std::to_string(seed));
            t.id = h.hex();
          }
          tasks.push_back(std::move(t));
        }
      }
    }
  }
  return tasks;
}

}  // namespace graftnav::app
