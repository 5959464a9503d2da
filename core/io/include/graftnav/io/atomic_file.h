#pragma once
// Atomic file output, the one writer of every result file: data go to a temporary file with a
// unique name in the destination's folder; commit() flushes and fsyncs it, renames it onto the
// destination and fsyncs the folder. A reader never sees a half-written file; a failure (full
// disk, exception, SIGKILL) leaves any previous file untouched, and every failure except a kill
// removes the temporary file. Errors throw std::runtime_error with the path and errno's text.

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
  // Flushes, fsyncs, closes and renames the temporary file onto the destination, then fsyncs the
  // folder. Throws on failure (the destination then keeps its previous content and the temporary
  // file is removed by the destructor).
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
