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
const char* const kNavColumns[] = {"week", "time", "latitude", "longitude", "height", "v_north",
                                   "v_east", "v_down", "roll", "pitch", "yaw"};
}  // namespace

NavReadPolicy NavReadPolicy::real() {
  NavReadPolicy p;
  p.duplicate_stamp = ReadRule::kRepair;
  p.backwards_stamp = ReadRule::kRepair;
  return p;
}

void NavReadPolicy::validate() const {
  requireRule(duplicate_stamp, {ReadRule::kError, ReadRule::kRepair}, "NavReadPolicy.duplicate_stamp");
  requireRule(backwards_stamp, {ReadRule::kError, ReadRule::kRepair}, "NavReadPolicy.backwards_stamp");
}

NavSeries readNav(const std::string& path, const NavReadPolicy& policy, ReadReport* report_out) {
  policy.validate();
  ReadReport local_report;
  ReadReport& report = report_out ? *report_out : local_report;
  report = ReadReport{};
  report.path = path;
  TextTableReader reader(path);
  NavSeries nav;
  nav.reserve(reader.physicalLineCount());
  TimeOrderGuard order(policy.duplicate_stamp, policy.backwards_stamp);
  while (reader.next()) {
    ++report.data_lines;
    reader.requireColumns(11, 11, "navigation .nav");
    reader.requireFinite(kNavColumns);
    const double* v = reader.values();
    const int week = reader.integerValue(0, "week");
    if (week < 0) reader.fail("week " + std::string(reader.token(0)) + " is negative");
    if (std::fabs(v[2]) > 90.0) reader.fail("latitude " + std::string(reader.token(2)) + " deg is outside [-90, 90]");
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

void writeNav(const std::string& path, const NavSeries& nav) {
  if (nav.empty()) throw std::invalid_argument(path + ": writeNav: no epochs");
  for (std::size_t k = 0; k < nav.size(); ++k) {
    const NavState& s = nav[k];
    if (!std::isfinite(s.t_s) || !std::isfinite(s.pos.lat_rad) || !std::isfinite(s.pos.lon_rad) ||
        !std::isfinite(s.pos.h_m) || !s.v_n.allFinite() || !s.q_nb.coeffs().allFinite())
      throw std::invalid_argument(path + ": writeNav: epoch " + std::to_string(k) + " has a non-finite value");
    if (k > 0 && !(s.gnss_week * kSecondsPerWeek + s.t_s > nav[k - 1].gnss_week * kSecondsPerWeek + nav[k - 1].t_s))
      throw std::invalid_argument(path + ": writeNav: epoch " + std::to_string(k) + " time " + std::to_string(s.gnss_week) +
                                  " " + fmt::format("{:.9f}", s.t_s) + " is not after the previous epoch");
  }
  AtomicFile file(path);
  fmt::memory_buffer buf;
  for (const NavState& s : nav) {
    const Eigen::Vector3d e_deg = eulerFromQuat(s.q_nb.normalized()) * units::kRadToDeg;
    double yaw_deg = e_deg.z() < 0.0 ? e_deg.z() + 360.0 : e_deg.z();
    if (yaw_deg >= 360.0) yaw_deg -= 360.0;
    fmt::format_to(std::back_inserter(buf), "{} {:.9f} {:.11f} {:.11f} {:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f}\n",
                   s.gnss_week, s.t_s, s.pos.lat_rad * units::kRadToDeg, s.pos.lon_rad * units::kRadToDeg, s.pos.h_m,
                   s.v_n.x(), s.v_n.y(), s.v_n.z(), e_deg.x(), e_deg.y(), yaw_deg);
    if (buf.size() > (1u << 20)) {
      file.write(std::string_view(buf.data(), buf.size()));
      buf.clear();
    }
  }
  file.write(std::string_view(buf.data(), buf.size()));
  file.commit();
}

}  // namespace graftnav
