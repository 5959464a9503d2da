#pragma once
// GNSS files (dataset.md):
//   gnss.pos          `sow lat_deg lon_deg h_m std_n_m std_e_m std_u_m`
//   gnss_fixtype.txt  `sow fix_type num_sv` (1 single point, 4 RTK fixed, 5 RTK float)
// Strict by default (errors name path:line and value); GnssReadPolicy::real() for real recordings.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/io/text_table.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct GnssReadPolicy {
  // Time equal to the previous: kError or kRepair (drop an identical line; differing = error).
  ReadRule duplicate_stamp = ReadRule::kError;
  // Time before the previous: kError or kRepair (drop the line).
  ReadRule backwards_stamp = ReadRule::kError;
  // Epoch more than whole_second_tolerance_s off a whole second: kWarn (counted only) or kError.
  // Counted in both policies: 5-10 Hz receivers and receive-time stamps are legitimate.
  ReadRule off_whole_second = ReadRule::kWarn;
  double whole_second_tolerance_s = 1e-3;
  // A standard deviation of exactly 0: kError or kRepair (replaced by std_floor_m). Negative
  // standard deviations are always an error.
  ReadRule zero_std = ReadRule::kError;
  double std_floor_m = 0.005;
  // Fix-type epochs with no .pos epoch within match_tolerance_s, or .pos epochs without a fix-type
  // epoch: kError or kWarn (counted; such a .pos epoch keeps fix_type 0 = unknown).
  ReadRule unmatched_fix_type = ReadRule::kError;
  double match_tolerance_s = 1e-3;

  static GnssReadPolicy strict() { return {}; }
  // Repair duplicates, backwards stamps and zero std; count off-second and unmatched epochs.
  static GnssReadPolicy real();
  void validate() const;  // throws std::invalid_argument naming the field
};

// Reads a .pos file. Throws std::runtime_error naming path:line for a missing file, an empty file,
// a malformed line, a column count other than 7, NaN/inf, latitude outside [-90, 90], a negative
// std, and the conditions whose rule is kError.
GnssSeries readGnssPos(const std::string& path, const GnssReadPolicy& policy = {},
                       ReadReport* report = nullptr);

struct GnssFixTypeRecord {
  double t_s = 0.0;
  int fix_type = 0;
  int num_sv = 0;
  int line = 0;  // line in the file, for messages
};
// Reads gnss_fixtype.txt (3 integer-valued columns after the time). Same time-order rules.
std::vector<GnssFixTypeRecord> readGnssFixTypes(const std::string& path,
                                                const GnssReadPolicy& policy = {},
                                                ReadReport* report = nullptr);

// Sets fix_type and num_sv of each fix whose time matches a record within
// policy.match_tolerance_s. Unmatched records / fixes follow policy.unmatched_fix_type (counted
// under ReadCondition::kUnmatchedEpoch in *report). fixtype_path is only used in messages.
void mergeGnssFixTypes(GnssSeries& fixes, const std::vector<GnssFixTypeRecord>& records,
                       const std::string& fixtype_path, const GnssReadPolicy& policy = {},
                       ReadReport* report = nullptr);

// readGnssPos + (when fixtype_path is non-empty) readGnssFixTypes + mergeGnssFixTypes.
// The reports of the two files are appended to *reports when given.
GnssSeries readGnss(const std::string& pos_path, const std::string& fixtype_path,
                    const GnssReadPolicy& policy = {}, std::vector<ReadReport>* reports = nullptr);

// readGnss one epoch at a time: each file read through a streaming text window, so memory does
// not grow with the files' length. The same checks, repairs, fixes and reports as readGnss (an
// error in either file is met when the pass reaches it, so of two errors in the two files the
// earlier in time is reported, not the .pos file's). One pass; open another reader for more.
class GnssStreamReader {
 public:
  // fixtype_path empty: no fix-type file. Each file is read in chunks of about chunk_bytes
  // (default 64 KiB: ~900 epochs of .pos; the reader holds up to twice that per file). Throws
  // std::runtime_error when a file cannot be opened.
  GnssStreamReader(const std::string& pos_path, const std::string& fixtype_path,
                   const GnssReadPolicy& policy = {}, std::size_t chunk_bytes = kDefaultChunkBytes);
  static constexpr std::size_t kDefaultChunkBytes = std::size_t{1} << 16;
  ~GnssStreamReader();
  GnssStreamReader(const GnssStreamReader&) = delete;
  GnssStreamReader& operator=(const GnssStreamReader&) = delete;
  // The next fix into *fix; false at the end (then the reports are complete). Throws as readGnss.
  bool next(GnssFix* fix);
  // The .pos report, then the fix-type report when there is that file (as readGnss's).
  std::vector<ReadReport> reports() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Writers, atomic: time %.6f, lat/lon %.10f deg, height %.4f m, std %.4f m (std up = std_ned_m.z).
// Throw std::invalid_argument on non-finite values or times not strictly increasing.
void writeGnssPos(const std::string& path, const GnssSeries& fixes);
// `sow fix_type num_sv` with time %.6f.
void writeGnssFixTypes(const std::string& path, const GnssSeries& fixes);

}  // namespace graftnav
