#pragma once
// Navigation files (.nav, dataset.md): `week sow lat_deg lon_deg h_m vn ve vd roll_deg pitch_deg
// yaw_deg`; Euler angles are ZYX of body (FRD) in NED, converted to/from q_nb with rotation.h.
// NavState.t_s is the seconds of week, NavState.gnss_week the week. Times must increase
// (compared as week * 604800 + sow, so a week rollover is allowed).

#include <cstddef>
#include <memory>
#include <string>

#include "graftnav/io/text_table.h"
#include "graftnav/nav/nav_source.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct NavReadPolicy {
  ReadRule duplicate_stamp = ReadRule::kError;  // kError | kRepair (drop an identical line)
  ReadRule backwards_stamp = ReadRule::kError;  // kError | kRepair (drop the line)
  static NavReadPolicy strict() { return {}; }
  static NavReadPolicy real();  // repair both
  void validate() const;
};

// Throws std::runtime_error naming path:line for a missing or empty file, a malformed line, a column
// count other than 11, NaN/inf, a non-integer or negative week, latitude outside [-90, 90], and the
// conditions whose rule is kError.
NavSeries readNav(const std::string& path, const NavReadPolicy& policy = {},
                  ReadReport* report = nullptr);

// readNav one epoch at a time, in a chunk of text at a time: memory does not grow with the file.
// The epochs, the report and the errors equal readNav's (an error is thrown when the line holding
// it is read, so a caller may have used earlier epochs already); at the end of a file without
// epochs next() throws as readNav does.
class NavStreamReader final : public NavSource {
 public:
  NavStreamReader(const std::string& path, const NavReadPolicy& policy = {});
  bool next(NavState* state) override;
  // Counts so far; complete once next() has returned false.
  const ReadReport& report() const { return report_; }

 private:
  TextTableReader reader_;
  TimeOrderGuard order_;
  ReadReport report_;
};

// Passes over a .nav file, each through a new NavStreamReader.
NavOpenFn navFileSource(const std::string& path, const NavReadPolicy& policy = {});

// Atomic writer: week %d, sow %.9f, lat/lon %.11f deg, height %.6f m, velocity %.6f m/s, roll and
// pitch %.9f deg, yaw %.9f deg in [0, 360). Throws std::invalid_argument on non-finite values or
// times not strictly increasing.
void writeNav(const std::string& path, const NavSeries& nav);

class AtomicFile;

// writeNav one epoch at a time, for output that is not held in memory: the same checks (named
// by the epoch's index) and byte-identical text. The file appears at the destination only on
// commit(); if an exception leaves it uncommitted, the destination keeps its previous content.
class NavWriter {
 public:
  explicit NavWriter(const std::string& path);  // throws std::runtime_error like AtomicFile
  ~NavWriter();
  NavWriter(const NavWriter&) = delete;
  NavWriter& operator=(const NavWriter&) = delete;
  void add(const NavState& state);
  void commit();  // throws std::invalid_argument when no epoch was added
  std::size_t count() const { return count_; }

 private:
  std::unique_ptr<AtomicFile> file_;
  std::string buffer_;
  NavState prev_;
  std::size_t count_ = 0;
};

}  // namespace graftnav
