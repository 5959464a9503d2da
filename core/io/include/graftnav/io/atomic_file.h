#pragma once
// Atomic file output: data goes to a temporary file in the destination's directory and is renamed
// onto the destination only by commit(), so a reader never sees a half-written file and a failure
// (exception, crash) leaves any previous file untouched.

#include <cstdio>
#include <string>
#include <string_view>

namespace graftnav {

class AtomicFile {
 public:
  // Creates "<dir>/.<name>.tmp.XXXXXX" next to path. Throws std::runtime_error naming the path when
  // the directory does not exist or is not writable.
  explicit AtomicFile(std::string path);
  // Removes the temporary file unless commit() succeeded.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Buffered write; throws std::runtime_error on an I/O error (e.g. disk full).
  void write(std::string_view data);
  // Flushes, closes and renames the temporary file onto the destination. Throws on failure (the
  // destination then keeps its previous content).
  void commit();

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string tmp_path_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Writes the whole content atomically (AtomicFile + commit).
void writeFileAtomically(const std::string& path, std::string_view content);

}  // namespace graftnav
