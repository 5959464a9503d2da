#include "graftnav/io/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace graftnav {

namespace {
std::string errnoText() { return std::strerror(errno); }
}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  const std::filesystem::path p(path_);
  if (p.filename().empty()) throw std::runtime_error(path_ + ": not a file path");
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  std::string templ = (dir / ("." + p.filename().string() + ".tmp.XXXXXX")).string();
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  const int fd = ::mkstemp(buf.data());
  if (fd < 0) throw std::runtime_error(path_ + ": cannot create a temporary file in '" + dir.string() + "': " + errnoText());
  tmp_path_ = buf.data();
  // mkstemp creates mode 0600; give the usual permissions (subject to umask).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    ::close(fd);
    std::remove(tmp_path_.c_str());
    throw std::runtime_error(path_ + ": cannot open temporary file: " + errnoText());
  }
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !tmp_path_.empty()) std::remove(tmp_path_.c_str());
}

void AtomicFile::write(std::string_view data) {
  if (!file_) throw std::runtime_error(path_ + ": write after commit");
  if (data.empty()) return;
  if (std::fwrite(data.data(), 1, data.size(), file_) != data.size())
    throw std::runtime_error(path_ + ": write failed: " + errnoText());
}

void AtomicFile::commit() {
  if (!file_) throw std::runtime_error(path_ + ": commit called twice");
  const bool flushed = std::fflush(file_) == 0;
  const int close_rc = std::fclose(file_);
  file_ = nullptr;
  if (!flushed || close_rc != 0) throw std::runtime_error(path_ + ": write failed: " + errnoText());
  if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0)
    throw std::runtime_error(path_ + ": cannot rename temporary file into place: " + errnoText());
  committed_ = true;
}

void writeFileAtomically(const std::string& path, std::string_view content) {
  AtomicFile f(path);
  f.write(content);
  f.commit();
}

}  // namespace graftnav
