#include "graftnav/io/nav_io.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"

namespace graftnav {

namespace {
constexpr double kSecondsPerWeek = 604800.0;
const char* const kNavColumns[] = {"week",   "time",   "latitude", "longitude", "height", "v_north",
                                   "v_east", "v_down", "roll",     "pitch",     "yaw"};
}  // namespace

NavReadPolicy NavReadPolicy::real() {
  NavReadPolicy p;
  p.duplicate_stamp = ReadRule::kRepair;
  p.backwards_stamp = ReadRule::kRepair;
  return p;
}

void NavReadPolicy::validate() const {
  requireRule(duplicate_stamp, {ReadRule::kError, ReadRule::kRepair},
              "NavReadPolicy.duplicate_stamp");
  requireRule(backwards_stamp, {ReadRule::kError, ReadRule::kRepair},
              "NavReadPolicy.backwards_stamp");
}

NavSeries readNav(const std::string& path, const NavReadPolicy& policy, ReadReport* report_out) {
  policy.validate();
  ReadReport local_report;
  ReadReport& report = report_out ? *report_out : local_report;
  report = ReadReport{};
  report.path = path;
  // Streamed: the file's text is not held next to the series (a 200 Hz truth of an hour is
  // ~90 MB of text).
  NavSeries nav;
  nav.reserve(countPhysicalLines(path));
  TextTableReader reader = TextTableReader::streaming(path);
  TimeOrderGuard order(policy.duplicate_stamp, policy.backwards_stamp);
  while (reader.next()) {
    ++report.data_lines;
    reader.requireColumns(11, 11, "navigation .nav");
    reader.requireFinite(kNavColumns);
    const double* v = reader.values();
    const int week = reader.integerValue(0, "week");
    if (week < 0) reader.fail("week " + std::string(reader.token(0)) + " is negative");
    if (std::fabs(v[2]) > 90.0)
      reader.fail("latitude " + std::string(reader.token(2)) + " deg is outside [-90, 90]");
    if (!order.accept(reader, week * kSecondsPerWeek + v[1], 1, report)) continue;
    NavState s;
    s.gnss_week = week;
    s.t_s = v[1];
    s.pos = Geodetic{v[2] * units::kDegToRad, v[3] * units::kDegToRad, v[4]};
    s.v_n = Eigen::Vector3d(v[5], v[6], v[7]);
    s.q_nb = quatFromEuler(Eigen::Vector3d(v[8], v[9], v[10]) * units::kDegToRad);
    nav.push_back(s);
  }
  if (nav.empty()) throw std::runtime_error(path + ": no navigation epochs in the file");
  report.records_kept = static_cast<int>(nav.size());
  return nav;
}

namespace {
// Throws std::invalid_argument when epoch k is not finite or not after the previous epoch.
void checkNavEpoch(const std::string& path, std::size_t k, const NavState& s,
                   const NavState* prev) {
  if (!std::isfinite(s.t_s) || !std::isfinite(s.pos.lat_rad) || !std::isfinite(s.pos.lon_rad) ||
      !std::isfinite(s.pos.h_m) || !s.v_n.allFinite() || !s.q_nb.coeffs().allFinite())
    throw std::invalid_argument(path + ": writeNav: epoch " + std::to_string(k) +
                                " has a non-finite value");
  if (prev &&
      !(s.gnss_week * kSecondsPerWeek + s.t_s > prev->gnss_week * kSecondsPerWeek + prev->t_s))
    throw std::invalid_argument(path + ": writeNav: epoch " + std::to_string(k) + " time " +
                                std::to_string(s.gnss_week) + " " + fmt::format("{:.9f}", s.t_s) +
                                " is not after the previous epoch");
}

template <typename Buffer>
void appendNavLine(Buffer& buf, const NavState& s) {
  const Eigen::Vector3d e_deg = eulerFromQuat(s.q_nb.normalized()) * units::kRadToDeg;
  double yaw_deg = e_deg.z() < 0.0 ? e_deg.z() + 360.0 : e_deg.z();
  if (yaw_deg >= 360.0) yaw_deg -= 360.0;
  fmt::format_to(std::back_inserter(buf),
                 "{} {:.9f} {:.11f} {:.11f} {:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f}\n",
                 s.gnss_week, s.t_s, s.pos.lat_rad * units::kRadToDeg,
                 s.pos.lon_rad * units::kRadToDeg, s.pos.h_m, s.v_n.x(), s.v_n.y(), s.v_n.z(),
                 e_deg.x(), e_deg.y(), yaw_deg);
}

constexpr std::size_t kFlushBytes = 1u << 20;
}  // namespace

void writeNav(const std::string& path, const NavSeries& nav) {
  if (nav.empty()) throw std::invalid_argument(path + ": writeNav: no epochs");
  for (std::size_t k = 0; k < nav.size(); ++k)
    checkNavEpoch(path, k, nav[k], k > 0 ? &nav[k - 1] : nullptr);
  AtomicFile file(path);
  fmt::memory_buffer buf;
  for (const NavState& s : nav) {
    appendNavLine(buf, s);
    if (buf.size() > kFlushBytes) {
      file.write(std::string_view(buf.data(), buf.size()));
      buf.clear();
    }
  }
  file.write(std::string_view(buf.data(), buf.size()));
  file.commit();
}

NavWriter::NavWriter(const std::string& path) : file_(std::make_unique<AtomicFile>(path)) {
  buffer_.reserve(kFlushBytes + 256);
}

NavWriter::~NavWriter() = default;

void NavWriter::add(const NavState& s) {
  checkNavEpoch(file_->path(), count_, s, count_ > 0 ? &prev_ : nullptr);
  appendNavLine(buffer_, s);
  prev_ = s;
  ++count_;
  if (buffer_.size() > kFlushBytes) {
    file_->write(buffer_);
    buffer_.clear();
  }
}

void NavWriter::commit() {
  if (count_ == 0) throw std::invalid_argument(file_->path() + ": writeNav: no epochs");
  file_->write(buffer_);
  buffer_.clear();
  file_->commit();
}

}  // namespace graftnav
