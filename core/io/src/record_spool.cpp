#include "graftnav/io/record_spool.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

namespace graftnav {
namespace {

constexpr std::size_t kBufferDoubles = 1 << 15;  // 256 KiB per write

std::string systemError() { return std::strerror(errno); }

}  // namespace

RecordSpool::RecordSpool(std::size_t doubles_per_record, const std::string& directory)
    : directory_(directory.empty() ? std::filesystem::temp_directory_path().string() : directory),
      width_(doubles_per_record) {
  if (width_ == 0) throw std::invalid_argument("RecordSpool: records need at least one value");
  std::string name = directory_ + "/graftnav-spool-XXXXXX";
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0)
    throw std::runtime_error("cannot create a temporary file in '" + directory_ +
                             "': " + systemError() +
                             (directory.empty() ? " (set TMPDIR to a writable directory)" : ""));
  ::unlink(name.c_str());
  buffer_.reserve(kBufferDoubles + width_);
}

RecordSpool::~RecordSpool() {
  if (fd_ >= 0) ::close(fd_);
}

void RecordSpool::append(const double* record) {
  if (finished_) throw std::logic_error("RecordSpool::append after finish()");
  buffer_.insert(buffer_.end(), record, record + width_);
  ++records_;
  if (buffer_.size() >= kBufferDoubles) flush();
}

void RecordSpool::append(const double* records, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) append(records + i * width_);
}

void RecordSpool::flush() {
  const char* p = reinterpret_cast<const char*>(buffer_.data());
  std::size_t left = buffer_.size() * sizeof(double);
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw std::runtime_error("cannot write a temporary file in '" + directory_ +
                               "': " + systemError());
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void RecordSpool::finish() {
  if (finished_) return;
  flush();
  buffer_.shrink_to_fit();
  finished_ = true;
}

void RecordSpool::read(std::size_t first, std::size_t count, std::vector<double>* out) const {
  if (!finished_) throw std::logic_error("RecordSpool::read before finish()");
  if (first > records_ || count > records_ - first)
    throw std::out_of_range("RecordSpool::read: records " + std::to_string(first) + " + " +
                            std::to_string(count) + " of " + std::to_string(records_));
  out->resize(count * width_);
  char* p = reinterpret_cast<char*>(out->data());
  std::size_t left = out->size() * sizeof(double);
  auto offset = static_cast<off_t>(first * width_ * sizeof(double));
  while (left > 0) {
    const ssize_t n = ::pread(fd_, p, left, offset);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("cannot read a temporary file back: " + systemError());
    p += n;
    offset += n;
    left -= static_cast<std::size_t>(n);
  }
}

RecordPass::RecordPass(std::shared_ptr<const RecordSpool> spool, std::size_t block_records)
    : spool_(std::move(spool)), block_(block_records == 0 ? 1 : block_records) {}

const double* RecordPass::next() {
  if (k_ == loaded_) {
    if (begin_ + loaded_ >= spool_->size()) return nullptr;
    begin_ += loaded_;
    loaded_ = std::min(block_, spool_->size() - begin_);
    spool_->read(begin_, loaded_, &raw_);
    k_ = 0;
  }
  return &raw_[(k_++) * spool_->recordDoubles()];
}

}  // namespace graftnav
