#include "graftnav/navigate/streamed_imu_file.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/case/file_streams.h"
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
  if (range.empty()) return imuFileStream(sel.path, sel.read_options);
  const std::string path = sel.path;
  const ImuReadOptions options = sel.read_options;
  return [path, options, range](const ImuBlockFn& emit) {
    ImuBlockReader reader(path, options);
    ImuSeries block, kept;
    while (reader.next(&block)) {
      std::size_t n_kept = 0;
      for (const ImuSample& s : block) n_kept += range.keepsImuSample(s.t_s, s.dt_s) ? 1 : 0;
      if (n_kept == block.size()) {  // inside the range: the block as it was read
        emit(block);
        continue;
      }
      kept.clear();
      for (const ImuSample& s : block)
        if (range.keepsImuSample(s.t_s, s.dt_s)) kept.push_back(s);
      if (!kept.empty()) emit(kept);
      if (block.back().t_s > range.endS()) return;
    }
  };
}

ImuSeries imuPrefix(const ImuSelection& sel, const ImuSeries& span, const TimeRangeConfig& range,
                    double t_end_s, bool* complete) {
  ImuBlockReader reader(sel.path, sel.read_options);
  ImuSeries block, prefix;
  // The samples through t_end_s at the nominal rate: no doubling of the capacity past them.
  const double rate_hz = sel.read_options.nominal_rate_hz;
  const double length_s = t_end_s - (span.front().t_s - span.front().dt_s);
  if (rate_hz > 0.0 && length_s > 0.0 && length_s < 1e6)
    prefix.reserve(static_cast<std::size_t>(length_s * rate_hz * 1.01) + 8);
  *complete = true;
  while (reader.next(&block)) {
    for (const ImuSample& s : block) {
      if (s.t_s > range.endS()) return prefix;  // a range that ends first
      if (!range.keepsImuSample(s.t_s, s.dt_s)) continue;
      prefix.push_back(s);
      if (s.t_s <= t_end_s + 1e-9) continue;
      *complete = !(s.t_s < span.back().t_s);
      if (!*complete) prefix.push_back(span.back());
      return prefix;
    }
  }
  return prefix;
}

ImuSeries alignmentPrefix(const ImuSelection& sel, const RunConfig& rc, const ImuSeries& span,
                          const TimeRangeConfig& range) {
  if (rc.alignment.mode != AlignmentMode::kStatic) return span;
  const double t_end_s = span.front().t_s - span.front().dt_s + rc.alignment.static_duration_s;
  bool complete = false;
  return imuPrefix(sel, span, range, t_end_s, &complete);
}

std::string keepHeldGnssInRange(const TimeRangeConfig& range, const ImuFileScan& scan,
                                GnssSeries* fixes) {
  GnssSeries kept;
  for (const GnssFix& f : *fixes)
    if (range.keepsGnssEpoch(f.t_s)) kept.push_back(f);
  const std::string note =
      timeRangeNote(scan.span, scan.kept, scan.total, static_cast<long>(kept.size()),
                    static_cast<long>(fixes->size()));
  *fixes = std::move(kept);
  return note;
}

GnssOpenFn gnssRangeStream(GnssOpenFn fixes, const TimeRangeConfig& range) {
  if (range.empty()) return fixes;
  return [fixes, range]() -> std::unique_ptr<GnssSource> {
    return std::make_unique<GnssInRange>(fixes(), range);
  };
}

}  // namespace graftnav
