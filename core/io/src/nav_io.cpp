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

NavStreamReader::NavStreamReader(const std::string& path, const NavReadPolicy& policy)
    : reader_(TextTableReader::streaming(path)),
      order_(policy.duplicate_stamp, policy.backwards_stamp) {
  policy.validate();
  report_.path = path;
}

bool NavStreamReader::next(NavState* state) {
  while (reader_.next()) {
    ++report_.data_lines;
    reader_.requireColumns(11, 11, "navigation .nav");
    reader_.requireFinite(kNavColumns);
    const double* v = reader_.values();
    const int week = reader_.integerValue(0, "week");
    if (week < 0) reader_.fail("week " + std::string(reader_.token(0)) + " is negative");
    if (std::fabs(v[2]) > 90.0)
      reader_.fail("latitude " + std::string(reader_.token(2)) + " deg is outside [-90, 90]");
    if (!order_.accept(reader_, week * kSecondsPerWeek + v[1], 1, report_)) continue;
    NavState& s = *state;
    s.gnss_week = week;
    s.t_s = v[1];
    s.pos = Geodetic{v[2] * units::kDegToRad, v[3] * units::kDegToRad, v[4]};
    s.v_n = Eigen::Vector3d(v[5], v[6], v[7]);
    s.q_nb = quatFromEuler(Eigen::Vector3d(v[8], v[9], v[10]) * units::kDegToRad);
    ++report_.records_kept;
    return true;
  }
  if (report_.records_kept == 0)
    throw std::runtime_error(report_.path + ": no navigation epochs in the file");
  return false;
}

NavSeries readNav(const std::string& path, const NavReadPolicy& policy, ReadReport* report_out) {
  policy.validate();
  // Streamed: the file's text is not held next to the series (a 200 Hz truth of an hour is
  // ~90 MB of text).
  NavSeries nav;
  nav.reserve(countPhysicalLines(path));
  NavStreamReader reader(path, policy);
  for (NavState s; reader.next(&s);) nav.push_back(s);
  if (report_out) *report_out = reader.report();
  return nav;
}

NavOpenFn navFileSource(const std::string& path, const NavReadPolicy& policy) {
  policy.validate();
  return [path, policy]() -> std::unique_ptr<NavSource> {
    return std::make_unique<NavStreamReader>(path, policy);
  };
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
