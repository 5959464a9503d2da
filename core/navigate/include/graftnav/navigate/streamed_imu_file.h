#pragma once
// The IMU file of a streamed run and what the run config keeps of it, never held whole: the
// samples of a time range (TimeRangeConfig::keepsImuSample, the rule of restrictToTimeRange) read
// in blocks, and for makeProblem only the samples a static alignment reads.
#include <string>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/run_config.h"
#include "graftnav/estimation/gnss_source.h"
#include "graftnav/estimation/nav_solution.h"

namespace graftnav {

// One read of an IMU file: the first and last samples a time range keeps and the counts.
struct ImuFileScan {
  ImuSeries span;  // the first and last kept samples
  long kept = 0;   // samples the range keeps (all without a range)
  long total = 0;  // samples of the file
};

// The file read once through the block reader, every line inside the range or not, so that its
// errors (physical range, time order, intervals; file and line) stop a streamed run before
// anything is written as they stop an in-memory read, and the lenient repair report
// (sel->read_summary) is known. Throws timeRangeWithoutSamples when the range keeps no sample.
// Memory stays flat.
ImuFileScan scanImuFile(ImuSelection* sel, const TimeRangeConfig& range = {});

// The samples of the file the range keeps, as one-pass blocks (each pass stops reading at the
// first sample after the range's end).
ImuPassFn imuRangeStream(const ImuSelection& sel, const TimeRangeConfig& range);

// The kept samples of the file through the first one after t_end_s, then the last kept sample
// (`span`: scanImuFile's), so that the series spans what the run navigates; *complete is set
// when no kept sample is left out (the file or the range ended first).
ImuSeries imuPrefix(const ImuSelection& sel, const ImuSeries& span, const TimeRangeConfig& range,
                    double t_end_s, bool* complete);

// What makeProblem reads of an IMU the estimators read as a file (`span`: scanImuFile's). With a
// static alignment: the kept samples through the first one after the alignment window
// (alignStatic stops there), then the last kept sample, so the problem's span is the run's.
// Otherwise `span`.
ImuSeries alignmentPrefix(const ImuSelection& sel, const RunConfig& rc, const ImuSeries& span,
                          const TimeRangeConfig& range = {});

// The held fixes a range keeps, as restrictToTimeRange keeps them, and the range's note (`scan`:
// scanImuFile's) for a run that streams the IMU and holds the GNSS.
std::string keepHeldGnssInRange(const TimeRangeConfig& range, const ImuFileScan& scan,
                                GnssSeries* fixes);

// The fixes of `fixes`' passes that the range keeps (TimeRangeConfig::keepsGnssEpoch).
GnssOpenFn gnssRangeStream(GnssOpenFn fixes, const TimeRangeConfig& range);

}  // namespace graftnav
