#include "graftnav/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace graftnav {

namespace {

std::string errnoText(int err) { return std::strerror(err); }

std::filesystem::path parentDir(const std::string& path) {
  const std::filesystem::path p(path);
  return p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
}

// Makes the rename itself durable: without an fsync of the folder a power cut after rename() may
// leave the old entry (or none) on disk even though the file's data were synced.
void syncDirectory(const std::string& path) {
  const std::string dir = parentDir(path).string();
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0)
    throw std::runtime_error(path + ": cannot open folder '" + dir +
                             "' to sync it: " + errnoText(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  // EINVAL: the file system does not support syncing a folder (nothing more can be done).
  if (rc != 0 && err != EINVAL)
    throw std::runtime_error(path + ": cannot sync folder '" + dir + "': " + errnoText(err));
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  const std::filesystem::path p(path_);
  if (p.filename().empty()) throw std::runtime_error(path_ + ": not a file path");
  const std::filesystem::path dir = parentDir(path_);
  std::string templ = (dir / ("." + p.filename().string() + ".tmp.XXXXXX")).string();
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  const int fd = ::mkstemp(buf.data());
  if (fd < 0)
    throw std::runtime_error(path_ + ": cannot create a temporary file in '" + dir.string() +
                             "': " + errnoText(errno));
  tmp_path_ = buf.data();
  // mkstemp creates mode 0600; give the usual permissions (subject to umask).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    const int err = errno;
    ::close(fd);
    std::remove(tmp_path_.c_str());
    throw std::runtime_error(path_ + ": cannot open temporary file: " + errnoText(err));
  }
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !tmp_path_.empty()) std::remove(tmp_path_.c_str());
}

void AtomicFile::write(std::string_view data) {
  if (!file_) throw std::runtime_error(path_ + ": write after commit or failure");
  if (data.empty()) return;
  if (std::fwrite(data.data(), 1, data.size(), file_) != data.size())
    throw std::runtime_error(path_ + ": write failed: " + errnoText(errno));
}

void AtomicFile::commit() {
  if (!file_) throw std::runtime_error(path_ + ": commit called twice or after a failure");
  // Flush the stdio buffer, then the kernel's: a rename of unsynced data can survive a power cut
  // as an empty or truncated file under the final name.
  int err = 0;
  if (std::fflush(file_) != 0) err = errno;
  if (err == 0 && ::fsync(::fileno(file_)) != 0) err = errno;
  const int close_rc = std::fclose(file_);
  if (err == 0 && close_rc != 0) err = errno;
  file_ = nullptr;
  if (err != 0) throw std::runtime_error(path_ + ": write failed: " + errnoText(err));
  if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0)
    throw std::runtime_error(path_ +
                             ": cannot rename temporary file into place: " + errnoText(errno));
  committed_ = true;
  syncDirectory(path_);
}

void writeFileAtomically(const std::string& path, std::string_view content) {
  AtomicFile f(path);
  f.write(content);
  f.commit();
}

}  // namespace graftnav
