#include "graftnav/eval/errors_csv.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav {

namespace {
// The text written to the file once it passes this size; the buffer's capacity is set once (a
// line more), so that it never doubles as the file grows.
constexpr std::size_t kFlushBytes = std::size_t{1} << 18;
constexpr std::size_t kLineBytes = 256;
}  // namespace

ErrorsCsvWriter::ErrorsCsvWriter(const std::string& path, double min_interval_s)
    : file_(std::make_unique<AtomicFile>(path)), min_interval_s_(min_interval_s) {
  buffer_.reserve(kFlushBytes + kLineBytes);
  buffer_ +=
      "t_s,north_m,east_m,down_m,horizontal_m,vn_m_s,ve_m_s,vd_m_s,roll_deg,pitch_deg,"
      "heading_deg,nees,outage\n";
}

ErrorsCsvWriter::~ErrorsCsvWriter() = default;

void ErrorsCsvWriter::add(const EpochError& e) {
  if (!failure_.empty() || e.t_s - last_t_s_ < min_interval_s_ - 1e-9) return;
  last_t_s_ = e.t_s;
  if (!e.pos_ned_m.allFinite() || !e.vel_ned_m_s.allFinite() || !e.euler_rad.allFinite()) {
    failure_ = fmt::format("{}: the error at t = {:.4f} s is not finite; refusing to write it",
                           file_->path(), e.t_s);
    return;
  }
  const double r2d = units::kRadToDeg;
  const std::string nees = std::isfinite(e.nees) ? fmt::format("{:.4g}", e.nees) : std::string();
  fmt::format_to(
      std::back_inserter(buffer_),
      "{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.5f},{:.5f},{:.5f},{:.6f},{:.6f},{:.6f},{},{}\n", e.t_s,
      e.pos_ned_m.x(), e.pos_ned_m.y(), e.pos_ned_m.z(), e.pos_ned_m.head<2>().norm(),
      e.vel_ned_m_s.x(), e.vel_ned_m_s.y(), e.vel_ned_m_s.z(), e.euler_rad.x() * r2d,
      e.euler_rad.y() * r2d, e.euler_rad.z() * r2d, nees, e.outage);
  if (buffer_.size() > kFlushBytes) {
    file_->write(buffer_);
    buffer_.clear();
  }
}

void ErrorsCsvWriter::commit() {
  if (!failure_.empty()) throw std::runtime_error(failure_);
  file_->write(buffer_);
  buffer_.clear();
  file_->commit();
}

}  // namespace graftnav
