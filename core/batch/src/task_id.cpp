#include "graftnav/batch/task_id.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace graftnav {
namespace fs = std::filesystem;

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

void addFileBytes(Fnv1a64& h, const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("batch: cannot read '" + file + "' to hash it");
  const std::uint64_t size = fs::file_size(file);
  h.add(&size, sizeof size);
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    h.add(buf, static_cast<std::size_t>(in.gcount()));
  }
}

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
    addFileBytes(h, f.string());
  }
  return h.hex();
}

}  // namespace graftnav
