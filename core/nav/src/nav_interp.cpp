#include "graftnav/nav/nav_interp.h"

#include <algorithm>
#include <cmath>

namespace graftnav {

NavState interpolateBetween(const NavState& a, const NavState& b, double t_s) {
  const double span = b.t_s - a.t_s;
  const double u = span > 0.0 ? std::clamp((t_s - a.t_s) / span, 0.0, 1.0) : 0.0;
  NavState s;
  s.t_s = t_s;
  s.gnss_week = a.gnss_week;
  s.pos.lat_rad = a.pos.lat_rad + u * (b.pos.lat_rad - a.pos.lat_rad);
  double dlon = b.pos.lon_rad - a.pos.lon_rad;  // across the antimeridian take the short way
  if (dlon > M_PI) dlon -= 2.0 * M_PI;
  if (dlon < -M_PI) dlon += 2.0 * M_PI;
  s.pos.lon_rad = a.pos.lon_rad + u * dlon;
  s.pos.h_m = a.pos.h_m + u * (b.pos.h_m - a.pos.h_m);
  s.v_n = a.v_n + u * (b.v_n - a.v_n);
  s.q_nb = a.q_nb.slerp(u, b.q_nb).normalized();
  return s;
}

NavInterpolator::NavInterpolator(const NavSeries& series, double tol_s)
    : series_(series), tol_s_(tol_s) {}

std::optional<NavState> NavInterpolator::at(double t_s) {
  const size_t n = series_.size();
  if (n == 0) return std::nullopt;
  if (t_s < series_.front().t_s - tol_s_ || t_s > series_.back().t_s + tol_s_) return std::nullopt;
  if (n == 1 || t_s <= series_.front().t_s) {
    NavState s = series_.front();
    s.t_s = t_s;
    return s;
  }
  if (t_s >= series_.back().t_s) {
    NavState s = series_.back();
    s.t_s = t_s;
    return s;
  }
  if (idx_ + 1 >= n || series_[idx_].t_s > t_s || (idx_ + 64 < n && series_[idx_ + 64].t_s < t_s)) {
    // Backwards or far-ahead query: binary search.
    auto it = std::upper_bound(series_.begin(), series_.end(), t_s,
                               [](double t, const NavState& s) { return t < s.t_s; });
    idx_ = static_cast<size_t>(std::distance(series_.begin(), it)) - 1;
  }
  while (idx_ + 1 < n && series_[idx_ + 1].t_s < t_s) ++idx_;
  const NavState& a = series_[idx_];
  const NavState& b = series_[std::min(idx_ + 1, n - 1)];
  return interpolateBetween(a, b, t_s);
}

std::optional<NavState> interpolateNav(const NavSeries& series, double t_s, double tol_s) {
  NavInterpolator it(series, tol_s);
  return it.at(t_s);
}

}  // namespace graftnav
