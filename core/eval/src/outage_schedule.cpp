#include "graftnav/eval/outage_schedule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

// Rules (also in docs/ekf.md):
//  * cfg.enabled == false, or an empty/inverted data span: no windows.
//  * Explicit list (cfg.explicit_windows non-empty, absolute times): each window must have
//    start_s < end_s (else std::invalid_argument naming the index). Windows are sorted and
//    overlapping or touching windows are merged. They are then clipped to [t_begin_s, t_end_s];
//    a window entirely outside the data is dropped. An explicit window may therefore start at the
//    data start (filter starts without GNSS) or run to the data end (GNSS never returns);
//    end_margin_s does not apply to explicit windows: the user asked for them.
//  * Periodic schedule: window k = [t_begin + start_s + k period_s, ... + length_s], k = 0, 1, ...
//    Requires length_s > 0, period_s >= length_s (else the windows would overlap; rejected) and
//    start_s >= 0 (start_s == 0: an outage at the very start). A window is kept only if it ends at
//    or before t_end_s - end_margin_s, so every periodic outage has the full length and outage
//    statistics stay comparable; windows past the end are dropped, never clipped.

namespace graftnav {

std::vector<TimeWindow> buildOutageWindows(const OutageScheduleConfig& cfg, double t_begin_s,
                                           double t_end_s) {
  std::vector<TimeWindow> out;
  if (!cfg.enabled || !(t_end_s > t_begin_s)) return out;

  if (!cfg.explicit_windows.empty()) {
    std::vector<TimeWindow> w = cfg.explicit_windows;
    for (size_t i = 0; i < w.size(); ++i) {
      if (!std::isfinite(w[i].start_s) || !std::isfinite(w[i].end_s) ||
          !(w[i].end_s > w[i].start_s)) {
        throw std::invalid_argument("buildOutageWindows: explicit window " + std::to_string(i) +
                                    " [" + std::to_string(w[i].start_s) + ", " +
                                    std::to_string(w[i].end_s) + "] must have start < end");
      }
    }
    std::sort(w.begin(), w.end(),
              [](const TimeWindow& a, const TimeWindow& b) { return a.start_s < b.start_s; });
    std::vector<TimeWindow> merged;
    for (const TimeWindow& x : w) {
      if (!merged.empty() && x.start_s <= merged.back().end_s) {
        merged.back().end_s = std::max(merged.back().end_s, x.end_s);
      } else {
        merged.push_back(x);
      }
    }
    for (TimeWindow x : merged) {
      x.start_s = std::max(x.start_s, t_begin_s);
      x.end_s = std::min(x.end_s, t_end_s);
      if (x.end_s > x.start_s) out.push_back(x);
    }
    return out;
  }

  if (!(cfg.length_s > 0.0) || !std::isfinite(cfg.length_s)) {
    throw std::invalid_argument("buildOutageWindows: length_s must be > 0, got " +
                                std::to_string(cfg.length_s));
  }
  if (!(cfg.period_s >= cfg.length_s) || !std::isfinite(cfg.period_s)) {
    throw std::invalid_argument("buildOutageWindows: period_s (" + std::to_string(cfg.period_s) +
                                ") must be >= length_s (" + std::to_string(cfg.length_s) + ")");
  }
  if (!(cfg.start_s >= 0.0) || !std::isfinite(cfg.start_s)) {
    throw std::invalid_argument("buildOutageWindows: start_s must be >= 0, got " +
                                std::to_string(cfg.start_s));
  }
  if (!(cfg.end_margin_s >= 0.0)) {
    throw std::invalid_argument("buildOutageWindows: end_margin_s must be >= 0, got " +
                                std::to_string(cfg.end_margin_s));
  }
  const double last_end = t_end_s - cfg.end_margin_s;
  for (long k = 0;; ++k) {
    TimeWindow x;
    x.start_s = t_begin_s + cfg.start_s + static_cast<double>(k) * cfg.period_s;
    x.end_s = x.start_s + cfg.length_s;
    if (x.end_s > last_end + 1e-9) break;
    out.push_back(x);
  }
  return out;
}

GnssSeries withholdGnss(const GnssSeries& gnss, const std::vector<TimeWindow>& outages) {
  GnssSeries out;
  out.reserve(gnss.size());
  for (const GnssFix& f : gnss) {
    bool inside = false;
    for (const TimeWindow& w : outages) {
      if (w.contains(f.t_s)) {
        inside = true;
        break;
      }
    }
    if (!inside) out.push_back(f);
  }
  return out;
}

}  // namespace graftnav
