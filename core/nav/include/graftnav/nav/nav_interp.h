#pragma once
// Interpolation of a navigation series in time: position linear in latitude, longitude and
// height, velocity linear, attitude by quaternion slerp. Used to compare a solution with a truth
// or reference series sampled at other epochs.

#include <optional>

#include "graftnav/nav/types.h"

namespace graftnav {

// The state of `series` (sorted by time) at t_s, or nullopt when t_s lies outside
// [front().t_s - tol_s, back().t_s + tol_s]. Times within tol_s of an end take the end state.
std::optional<NavState> interpolateNav(const NavSeries& series, double t_s, double tol_s = 1e-6);

// The same for a run of increasing query times: keeps the bracketing index between calls so a
// whole series is interpolated in linear time. Queries may go backwards (it then searches).
class NavInterpolator {
 public:
  explicit NavInterpolator(const NavSeries& series, double tol_s = 1e-6);
  std::optional<NavState> at(double t_s);

 private:
  const NavSeries& series_;
  double tol_s_;
  size_t idx_ = 0;
};

// Linear interpolation between two states at fraction u in [0, 1] (slerp for attitude).
NavState interpolateBetween(const NavState& a, const NavState& b, double t_s);

}  // namespace graftnav
