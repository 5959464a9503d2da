#pragma once
// Navigation states written once to a temporary binary file (io/record_spool.h) and read back as
// NavSources, each pass bit for bit what was written: SOL_REF read by every evaluation of a run
// without being held or parsed again.
#include <cstddef>
#include <memory>
#include <string>

#include "graftnav/nav/nav_source.h"
#include "graftnav/nav/types.h"

namespace graftnav {

class RecordSpool;

class NavSpool {
 public:
  // The file in `directory` (empty: TMPDIR), io/record_spool.h.
  explicit NavSpool(const std::string& directory = {});
  // Appends one state (before finish()).
  void add(const NavState& state);
  // Ends the writing; opener() may be called from now on.
  void finish();
  std::size_t size() const;
  const NavState& first() const { return first_; }
  const NavState& last() const { return last_; }
  // (count - 1) / span of the states written (0 with fewer than two or no span).
  double rateHz() const;
  // Opens a pass over the states; the passes keep the spool alive. Safe to call and to read from
  // several threads at once.
  NavOpenFn opener() const;

 private:
  std::shared_ptr<RecordSpool> spool_;
  NavState first_, last_;
};

// Every state of `source` into a finished spool.
NavSpool spoolNav(NavSource& source);

}  // namespace graftnav
