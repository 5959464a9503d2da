#include "graftnav/sg/power_on_errors.h"

#include <algorithm>
#include <cmath>

namespace graftnav {

PowerOnErrors::Vec6 PowerOnErrors::rate(double t_s) const {
  Vec6 r;
  r << gyro_bias_rad_s, accel_bias_m_s2;
  if (wander_knots.empty() || !(wander_step_s > 0.0)) return r;
  const double x = std::max(0.0, t_s) / wander_step_s;
  const std::size_t k = static_cast<std::size_t>(std::floor(x));
  if (k + 1 >= wander_knots.size()) return r + wander_knots.back();
  const double w = x - static_cast<double>(k);
  return r + (1.0 - w) * wander_knots[k] + w * wander_knots[k + 1];
}

PowerOnErrors::Vec6 PowerOnErrors::integral(double t0_s, double t1_s) const {
  // The rate is piecewise linear with knots far apart compared with one IMU interval, so the
  // mid-point rule is exact inside a knot interval and off by a second-order term across one.
  return rate(0.5 * (t0_s + t1_s)) * (t1_s - t0_s);
}

}  // namespace graftnav
