#pragma once
// A closed interval of time, in the seconds of the files' time axis (GNSS seconds of week).

namespace graftnav {

struct TimeWindow {
  double start_s = 0.0;
  double end_s = 0.0;
  bool contains(double t_s) const { return t_s >= start_s && t_s <= end_s; }
  double length_s() const { return end_s - start_s; }
};

}  // namespace graftnav
