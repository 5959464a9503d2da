#include "graftnav/navigate/streamed_imu_file.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/io/imu_io.h"

namespace graftnav {
namespace {

// The fixes of a pass that a time range keeps.
class GnssInRange final : public GnssSource {
 public:
  GnssInRange(std::unique_ptr<GnssSource> fixes, const TimeRangeConfig& range)
      : fixes_(std::move(fixes)), range_(range) {}
  bool next(GnssFix* fix) override {
    while (fixes_->next(fix))
      if (range_.keepsGnssEpoch(fix->t_s)) return true;
    return false;
  }

 private:
  std::unique_ptr<GnssSource> fixes_;
  TimeRangeConfig range_;
};

}  // namespace

ImuFileScan scanImuFile(ImuSelection* sel, const TimeRangeConfig& range) {
  ImuBlockReader reader(sel->path, sel->read_options);
  ImuSeries block;
  ImuFileScan scan;
  ImuSample first, last;
  while (reader.next(&block)) {
    if (scan.total == 0) first = block.front();
    last = block.back();
    scan.total += static_cast<long>(block.size());
    for (const ImuSample& s : block) {
      if (!range.keepsImuSample(s.t_s, s.dt_s)) continue;
      if (scan.kept == 0) scan.span = {s, s};
      scan.span.back() = s;
      ++scan.kept;
    }
  }
  sel->read_summary = reader.report().summary();
  if (scan.kept == 0) {
    if (scan.total == 0) throw std::runtime_error("IMU file '" + sel->path + "' holds no sample");
    throw timeRangeWithoutSamples(range, sel->path, first, last);
  }
  return scan;
}

ImuPassFn imuRangeStream(const ImuSelection& sel, const TimeRangeConfig& range) {
  const std::string path = sel.path;
  const ImuReadOptions options = sel.read_options;
  return [path, options, range](const ImuBlockFn& emit) {
    ImuBlockReader reader(path, options);
    ImuSeries block, kept;
    while (reader.next(&block)) {
      kept.clear();
      bool past_end = false;
      for (const ImuSample& s : block) {
        if (range.keepsImuSample(s.t_s, s.dt_s)) kept.push_back(s);
        past_end = past_end || s.t_s > range.endS();
      }
      if (!kept.empty()) emit(kept);
      if (past_end) return;
    }
  };
}

ImuSeries alignmentPrefix(const ImuSelection& sel, const RunConfig& rc, const ImuSeries& span,
                          const TimeRangeConfig& range) {
  if (rc.alignment.mode != AlignmentMode::kStatic) return span;
  const double t_end_s = span.front().t_s - span.front().dt_s + rc.alignment.static_duration_s;
  ImuBlockReader reader(sel.path, sel.read_options);
  ImuSeries block, prefix;
  // The window's samples at the nominal rate: no doubling of the capacity past them.
  const double rate_hz = sel.read_options.nominal_rate_hz;
  if (rate_hz > 0.0)
    prefix.reserve(static_cast<std::size_t>(rc.alignment.static_duration_s * rate_hz * 1.01) + 8);
  while (reader.next(&block)) {
    for (const ImuSample& s : block) {
      if (s.t_s > range.endS()) return prefix;  // a range shorter than the window
      if (!range.keepsImuSample(s.t_s, s.dt_s)) continue;
      prefix.push_back(s);
      if (s.t_s <= t_end_s + 1e-9) continue;
      if (s.t_s < span.back().t_s) prefix.push_back(span.back());
      return prefix;
    }
  }
  return prefix;
}

GnssOpenFn gnssRangeStream(GnssOpenFn fixes, const TimeRangeConfig& range) {
  if (range.empty()) return fixes;
  return [fixes, range]() -> std::unique_ptr<GnssSource> {
    return std::make_unique<GnssInRange>(fixes(), range);
  };
}

}  // namespace graftnav
