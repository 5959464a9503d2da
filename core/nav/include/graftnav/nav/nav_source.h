#pragma once
// Navigation states one at a time, in time order: a reference or a solution read as it is needed
// (a .nav file read in chunks, core/io's NavStreamReader) instead of held as a series.

#include <functional>
#include <memory>

#include "graftnav/nav/types.h"

namespace graftnav {

class NavSource {
 public:
  virtual ~NavSource() = default;
  // The next state into *state; false at the end.
  virtual bool next(NavState* state) = 0;
};

// Opens a new pass over the states (a consumer that reads them more than once opens it again).
using NavOpenFn = std::function<std::unique_ptr<NavSource>()>;

// A pass over a series held elsewhere (`series` must outlive the source).
std::unique_ptr<NavSource> seriesNavSource(const NavSeries& series);

}  // namespace graftnav
