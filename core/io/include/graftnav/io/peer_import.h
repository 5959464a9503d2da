#pragma once
// A graftnav case folder built from a peer's set-up (peer_config.h), so that `graftnav navigate
// CASE` reproduces the peer's run:
//
//   CASE/case.yaml          name, IMU rate, the peer's IMU noise as reference_imu, lever arm,
//                           initial state at the start time, reference_solution when given
//   CASE/field/ref_imu.txt  the peer's IMU file (linked; copied with 7 columns when it has more)
//   CASE/field/odometer.txt OB_GINS's odometer column(s) of the IMU file (imudatalen 8 or 9)
//   CASE/field/gnss.pos     the peer's GNSS file (linked, or copied with ImportOptions::copy_files)
//   CASE/field/reference.nav  optional reference solution for the errors (linked or copied)
//   CASE/run.yaml           run config: time_range, outages.windows, ekf initial sigmas, gnss, fgo,
//                           odometer
//   CASE/notes.md           what was converted, assumed or not converted (also returned)
//   CASE/source/<name>.yaml the peer's yaml, copied for the record
//
// Outage windows: OB_GINS's schedule when isuseoutage is true; otherwise the gaps of the peer's
// GNSS file longer than ImportOptions::min_gap_s inside the time range (a KF-GINS user makes
// outages by deleting GNSS epochs). A gap's window spans from just after the last fix before it to
// just before the first fix after it, so every GNSS epoch of the file is still used.

#include <string>
#include <vector>

#include "graftnav/io/peer_config.h"
#include "graftnav/nav/time_window.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct ImportOptions {
  // A GNSS gap is an outage when the time between two consecutive fixes exceeds
  // max(min_gap_s, gap_factor * median fix interval). Defaults: 3 s and 5 intervals, so 1 Hz or
  // 10 Hz data with a lost epoch or two do not make outages.
  double min_gap_s = 3.0;
  double gap_factor = 5.0;
  bool copy_files = false;     // copy the data files instead of linking them
  std::string reference_path;  // optional reference solution (.nav) for the errors
  std::string case_name;       // default: the peer yaml's file stem
  void validate() const;       // throws std::invalid_argument naming the field
};

// Gaps of `gnss` inside [t_begin_s, t_end_s] longer than the threshold above, as outage windows.
std::vector<TimeWindow> gnssGapWindows(const GnssSeries& gnss, double t_begin_s, double t_end_s,
                                       const ImportOptions& options);

struct ImportResult {
  std::string case_dir;
  std::vector<TimeWindow> outages;
  std::vector<std::string> notes;  // PeerSetup::notes plus the importer's own
};

// Writes the case folder (created if missing; existing files of the same names are replaced).
// Throws std::runtime_error naming the file on a read or write error.
ImportResult importPeerSetup(const PeerSetup& setup, const std::string& case_dir,
                             const ImportOptions& options = {});

}  // namespace graftnav
