#pragma once
// An IMU recording that need not be held: one pass over its samples in blocks (ImuPassFn, as
// the streamed estimators take it), its first and last samples (the span a problem is built
// from) and its length. It is read from a file (case/file_streams.h), spooled once and read back
// from the spool (spooledRecording: a recording read many times, parsed once), held in memory
// (heldRecording), or made as it is read (a grafted realization, sg/evaluate_pipeline.h).
#include <cstddef>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct ImuRecording {
  ImuPassFn pass;
  ImuSample first, last;
  std::size_t samples = 0;
  // Start of the first sample's interval (the start of the data).
  double beginTime_s() const { return first.t_s - first.dt_s; }
  // The first and last samples as a series: what a problem's span checks read.
  ImuSeries span() const { return {first, last}; }
};

// A recording of a held series (shared by every pass). Throws std::invalid_argument when empty.
ImuRecording heldRecording(ImuSeries series);
// A recording of a series the caller keeps alive and unchanged while the recording is read (no
// copy; each pass hands out the series as one block). Throws std::invalid_argument when empty.
ImuRecording viewedRecording(const ImuSeries& series);
// Every sample of one pass.
ImuSeries collectRecording(const ImuRecording& recording);
// One pass of `source` written to a RecordSpool (io/record_spool.h); each pass of the recording
// reads the spool back in blocks of `block_samples`, the samples bit for bit. Throws
// std::invalid_argument when the source gives no sample.
ImuRecording spooledRecording(const ImuPassFn& source, std::size_t block_samples = 4096);

}  // namespace graftnav
