#include "graftnav/sg/sg_statistics.h"

#include <cmath>
#include <limits>

namespace graftnav {

std::array<double, 5> asArray(const DriftStats& s) {
  return {s.horizontal_m, s.vertical_m, s.roll_rad, s.pitch_rad, s.heading_rad};
}

DriftStats fromArray(const std::array<double, 5>& a) {
  DriftStats s;
  s.horizontal_m = a[0];
  s.vertical_m = a[1];
  s.roll_rad = a[2];
  s.pitch_rad = a[3];
  s.heading_rad = a[4];
  return s;
}

const std::array<std::string, 5>& driftStatNames() {
  static const std::array<std::string, 5> names{"horizontal_m", "vertical_m", "roll_deg",
                                                "pitch_deg", "heading_deg"};
  return names;
}

DriftStats relativeDifference(const DriftStats& err_x, const DriftStats& err_real) {
  const auto x = asArray(err_x);
  const auto r = asArray(err_real);
  std::array<double, 5> d;
  for (int i = 0; i < 5; ++i) {
    d[i] = (r[i] > 0.0 && std::isfinite(r[i]) && std::isfinite(x[i]))
               ? std::abs(x[i] - r[i]) / r[i]
               : std::numeric_limits<double>::quiet_NaN();
  }
  return fromArray(d);
}

}  // namespace graftnav
