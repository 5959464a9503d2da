#pragma once
// The outage schedule of a run: the run config's outages: section (or the defaults) with the
// values given on a command line, a batch task or a Python call over it. One rule for every
// command: a value given overrides the config's, the others stay.
#include <optional>

#include "graftnav/eval/outage_schedule.h"

namespace graftnav {

struct OutageOverrides {
  std::optional<double> length_s, period_s, start_s;

  bool any() const { return length_s || period_s || start_s; }
  // Lengths and periods > 0 and finite, the start >= 0 and finite, the period >= the length.
  // Throws std::runtime_error naming the value (--outage-length, --outage-period,
  // --outage-start: the spelling every interface shares).
  void validate() const;
  // `base` with the given values over it.
  OutageScheduleConfig appliedTo(OutageScheduleConfig base) const;
};

}  // namespace graftnav
