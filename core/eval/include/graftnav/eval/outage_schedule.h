#pragma once
// GNSS outage schedule: windows in which GNSS is withheld from an estimator, to measure how the
// IMU alone navigates (the seed's 60 s outages; the peers' "60 s every 180 s").

#include <vector>

#include "graftnav/nav/time_window.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct OutageScheduleConfig {
  double length_s = 60.0;      // outage length
  double period_s = 180.0;     // start-to-start spacing
  double start_s = 300.0;      // first outage start, seconds after the first IMU epoch (warm-up)
  double end_margin_s = 10.0;  // no outage may end closer than this to the data end
  std::vector<TimeWindow> explicit_windows;  // absolute times (s of week); overrides the above
  bool enabled = true;
};

// Builds the outage windows inside [t_begin_s, t_end_s]; windows that would overlap or run past
// the end are clipped or dropped by the rules documented in the implementation.
std::vector<TimeWindow> buildOutageWindows(const OutageScheduleConfig& cfg, double t_begin_s,
                                           double t_end_s);

// GNSS epochs with every fix inside an outage removed.
GnssSeries withholdGnss(const GnssSeries& gnss, const std::vector<TimeWindow>& outages);

}  // namespace graftnav
