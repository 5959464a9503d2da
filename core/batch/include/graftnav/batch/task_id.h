#pragma once
// The hash behind task ids: 64-bit FNV-1a, finalized, over everything that decides a task's
// result (tasks.h lists it). Editing a case file, a config or a profile changes the ids of the
// tasks that read it, so a resumed batch reruns exactly those.

#include <cstddef>
#include <cstdint>
#include <string>

namespace graftnav {

class Fnv1a64 {
 public:
  void add(const void* data, std::size_t size);
  void add(const std::string& s);  // the length, then the bytes (so fields cannot run together)
  std::uint64_t value() const { return h_; }
  std::string hex() const;  // finalized (task_id.cpp), 16 hex digits

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

// Adds the file's size and bytes; throws std::runtime_error naming it when it cannot be read.
void addFileBytes(Fnv1a64& h, const std::string& file);

// Hash of every regular file under dir: relative path and bytes, in sorted path order (symlinks
// followed). A folder that does not exist hashes as empty.
std::string hashFolder(const std::string& dir);

}  // namespace graftnav
