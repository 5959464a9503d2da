#pragma once
// GNSS fixes one at a time, in time order: what an estimator reads when the fixes need not be
// held (a file read as the run goes, core/io's GnssStreamReader) or when they are (a series).

#include <functional>
#include <memory>

#include "graftnav/nav/types.h"

namespace graftnav {

class GnssSource {
 public:
  virtual ~GnssSource() = default;
  // The next fix into *fix; false at the end.
  virtual bool next(GnssFix* fix) = 0;
};

// Opens a new pass over the fixes (an estimator that reads them more than once opens it again).
using GnssOpenFn = std::function<std::unique_ptr<GnssSource>()>;

// A pass over a series held elsewhere (`fixes` must outlive the source).
std::unique_ptr<GnssSource> seriesGnssSource(const GnssSeries& fixes);

}  // namespace graftnav
