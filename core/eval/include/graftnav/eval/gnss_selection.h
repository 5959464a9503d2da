#pragma once
// Selection of GNSS epochs by quality, and time-tag correction, before any estimator sees them.
//
// Real receivers mix single-point, RTK-float and RTK-fixed epochs and stamp some of them with the
// receive time instead of the measurement time. selectGnss() applies, in this order:
//   1. non-finite position or std            -> rejected (reason "non_finite")
//   2. fix type not in accepted_fix_types     -> rejected (reason "fix_type"); empty list = all
//   3. horizontal std (max of N, E) above max_horizontal_std_m, or vertical (U) std above
//      max_vertical_std_m                     -> rejected (reason "std")
//   4. time-tag correction: t_measured = t_tag - latency, latency from latency_s_by_fix_type
//      (else latency_s); the series is re-sorted because different fix types may move past each
//      other (counted as "reordered"); a kept epoch whose corrected time equals the previous
//      kept one's is dropped (reason "duplicate_time");
//   5. min_spacing_s > 0: of two kept epochs closer than this, the one with the larger horizontal
//      std is dropped (reason "spacing"; a factor graph cannot weigh a 10-ms IMU interval).
// Every epoch is either kept or counted under exactly one reason: input == used + rejected.

#include <map>
#include <string>
#include <vector>

#include "graftnav/nav/types.h"

namespace graftnav {

struct GnssSelectionOptions {
  std::vector<int> accepted_fix_types;  // empty: every fix type (0 unknown included)
  double max_horizontal_std_m = 1e9;    // reject when max(std_N, std_E) exceeds this
  double max_vertical_std_m = 1e9;      // reject when std_U exceeds this
  double latency_s = 0.0;               // time-tag latency of fix types not listed below
  std::map<int, double> latency_s_by_fix_type;
  double min_spacing_s = 0.0;  // 0: off
  // Throws std::invalid_argument naming the field.
  void validate() const;
  bool isIdentity() const;  // nothing would be rejected or shifted
};

struct GnssSelectionCounts {
  int input = 0;
  int used = 0;
  int rejected_non_finite = 0;
  int rejected_fix_type = 0;
  int rejected_std = 0;
  int rejected_duplicate_time = 0;
  int rejected_spacing = 0;
  int reordered = 0;  // epochs that changed order after the time-tag correction
  std::map<int, int> used_by_fix_type;
  std::map<int, int> input_by_fix_type;
  int rejected() const {
    return rejected_non_finite + rejected_fix_type + rejected_std + rejected_duplicate_time +
           rejected_spacing;
  }
  // One line: "GNSS selection: 7267 epochs in (fix 1: 6622, ...), used 463 (fix 4: 463), rejected ..."
  std::string summary() const;
};

struct GnssSelection {
  GnssSeries kept;
  GnssSelectionCounts counts;
};

GnssSelection selectGnss(const GnssSeries& gnss, const GnssSelectionOptions& options);

// The epochs of `gnss` whose fix type is in `fix_types` (all when empty), time tags corrected by
// the same latency rule (t - latency). Used to pick the withheld check points.
GnssSeries gnssOfFixTypes(const GnssSeries& gnss, const std::vector<int>& fix_types,
                          const GnssSelectionOptions& latency_rule);

}  // namespace graftnav
