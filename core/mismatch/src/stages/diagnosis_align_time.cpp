// The finder's first stages: align time (cross-correlation offset, realignment of a large one),
// the grid inside all three records, and the residual real - simulated on it.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <utility>
#include <vector>
#include <stdexcept>
#include <string>

#include "diagnosis_stages.h"
#include "graftnav/mismatch/streamed_binning.h"

namespace graftnav::diagnosis_detail {

namespace {

// Marks the bins of `grid` that overlap a sampling gap of any record (common_grid.h
// binsOverlappingGaps; `masks`, one per record) in out->masked_bins, lists them as spans with a
// note, and refuses a record of which more than half would be left out.
void maskSamplingGaps(std::initializer_list<std::vector<char>> masks, const GridSpec& grid,
                      DiagnosisResult* out) {
  const int n = grid.count;
  out->masked_bins.assign(n, 0);
  for (const std::vector<char>& m : masks)
    for (int i = 0; i < n; ++i) out->masked_bins[i] |= m[i];
  int masked = 0;
  std::string spans;
  for (int i = 0; i < n; ++i) {
    if (!out->masked_bins[i]) continue;
    ++masked;
    if (i == 0 || !out->masked_bins[i - 1]) {
      int j = i;
      while (j + 1 < n && out->masked_bins[j + 1]) ++j;
      out->masked_spans.push_back({grid.binStart(i), grid.binStart(j + 1)});
      if (out->masked_spans.size() <= 5)
        spans += fmt::format("{}{:.2f}-{:.2f}", spans.empty() ? "" : ", ", grid.binStart(i),
                             grid.binStart(j + 1));
    }
  }
  if (masked == 0) return;
  if (masked > n / 2)
    throw std::invalid_argument(fmt::format(
        "diagnose: {} of {} bins overlap sampling gaps of the records; too few are left", masked,
        n));
  out->notes.push_back(fmt::format(
      "{} bins ({:.2f} s) overlapping sampling gaps (an interval > 1.5 x the median) are left out "
      "of every fit and RMS: {} span(s), {}{}",
      masked, masked * grid.bin_s, out->masked_spans.size(), spans,
      out->masked_spans.size() > 5 ? ", ..." : ""));
}

// The recording with every tag moved back by shift_s, handed out in blocks of at most 4096 samples
// (a held recording is one block).
ImuRecording withTagsMovedBack(const ImuRecording& rec, double shift_s) {
  ImuRecording moved = rec;
  moved.first.t_s -= shift_s;
  moved.last.t_s -= shift_s;
  moved.pass = [source = rec.pass, shift_s](const ImuBlockFn& block) {
    constexpr std::size_t kBlock = 4096;
    ImuSeries part;
    source([&](const ImuSeries& b) {
      for (std::size_t i = 0; i < b.size(); i += kBlock) {
        part.assign(b.begin() + i, b.begin() + std::min(b.size(), i + kBlock));
        for (ImuSample& smp : part) smp.t_s -= shift_s;
        block(part);
      }
    });
  };
  return moved;
}

}  // namespace

// Time offset first (pivot of the time_offset regressor): the grid must leave room for it.
TimeAlignment alignTime(const DiagnosisInputs& in, ImuRecording real, const DiagnoseOptions& opt,
                        DiagnosisResult* out) {
  TimeAlignment al;
  al.as_tagged = std::move(real);
  const ImuRecording reference = viewedRecording(in.reference);
  double pivot = 0.0;
  try {
    out->time_offset_xcorr = estimateTimeOffset(reference, al.as_tagged, opt.time_offset);
    if (out->time_offset_xcorr.reliable)
      pivot = out->time_offset_xcorr.tau_s;
    else
      out->notes.push_back(fmt::format(
          "cross-correlation time offset not reliable (peak correlation {:.3f}); the time_offset "
          "term uses the derivative regressor",
          out->time_offset_xcorr.peak_correlation));
  } catch (const std::invalid_argument& e) {
    out->notes.push_back(std::string("time offset not estimated by cross-correlation: ") +
                         e.what());
  }
  // A large offset (separately started loggers) is taken out first: the real record's tags are
  // moved by it, so the joint fit's first-order shift of the other terms stays small, and the
  // remainder is estimated again; the offset reported adds both.
  if (std::abs(pivot) > opt.realign_offset_s) {
    al.realign_s = pivot;
    al.realigned = withTagsMovedBack(al.as_tagged, al.realign_s);
    pivot = 0.0;
    TimeOffsetOptions fine_only = opt.time_offset;  // the coarse peak is already taken out
    fine_only.coarse_max_offset_s = 0.0;
    const TimeOffsetEstimate rest = estimateTimeOffset(reference, al.realigned, fine_only);
    if (rest.reliable) pivot = rest.tau_s;
    out->notes.push_back(fmt::format(
        "time offset {:.4f} s (cross-correlation) is larger than {:.2f} s: the real record's tags "
        "were moved by it before binning; the time_offset reported adds the fitted remainder",
        al.realign_s, opt.realign_offset_s));
  }
  if (std::abs(pivot) < opt.finder.min_pivot_bins * opt.bin_s) pivot = 0.0;
  al.pivot_s = pivot;
  return al;
}

// Grid inside all three records, margin_s (or the offset plus 0.5 s) from their ends: the
// shifted reference x(t - tau) must exist on every bin.
GridSpec finderGrid(const DiagnosisInputs& in, const ImuRecording& simulated,
                    const ImuRecording& real, double pivot, const DiagnoseOptions& opt,
                    std::vector<std::string>* notes) {
  const double margin_s = std::max(opt.margin_s, std::abs(pivot) + opt.finder.pivot_margin_s);
  GridSpec grid = commonGrid(in.reference, real.span(), opt.bin_s, margin_s);
  {
    const GridSpec gs = commonGrid(simulated, real, opt.bin_s, margin_s);
    const double t0 = std::max(grid.t_begin_s, gs.t_begin_s);
    const double t1 = std::min(grid.binStart(grid.count), gs.binStart(gs.count));
    grid.t_begin_s = t0;
    grid.count = static_cast<int>(std::floor((t1 - t0) / opt.bin_s + 1e-9));
    if (grid.count < opt.finder.min_grid_bins)
      throw std::invalid_argument(
          fmt::format("diagnose: the records overlap by {} bins, fewer "
                      "than {} (finder.min_grid_bins)",
                      grid.count, opt.finder.min_grid_bins));
  }
  if (std::abs(pivot) > opt.margin_s)
    notes->push_back(fmt::format(
        "time offset {:.3f} s exceeds the {:.1f}-s margin: the grid keeps {:.3f} s from the "
        "records' ends",
        pivot, opt.margin_s, margin_s));
  return grid;
}

DiagnoseOptions optionsOnGrid(const DiagnosisInputs& in, const ImuRecording& simulated,
                              const GridSpec& grid, const DiagnoseOptions& opt_in) {
  const int n = grid.count;
  // Slow-noise blocks: slow_block_s, shortened so that a short record still has min_slow_blocks.
  DiagnoseOptions opt = opt_in;
  if (opt.selection.slow_block_bins == 0 && opt.slow_block_s > 0.0)
    opt.selection.slow_block_bins = std::min(
        static_cast<int>(std::round(opt.slow_block_s / opt.bin_s)), n / opt.finder.min_slow_blocks);
  opt.selection.bin_s = grid.bin_s;
  if (in.graft_static_record_s > 0.0 && simulated.samples > 0) {
    // The tiling clock starts at the simulation's first interval (grafting.cpp).
    const double t0 = simulated.beginTime_s();
    opt.selection.replay_period_s = in.graft_static_record_s;
    opt.selection.replay_start_s = in.graft_start_offset_s + (grid.t_begin_s - t0);
  }
  return opt;
}

namespace {

// A record's bins, read in one pass after its median interval: as binned (its tags moved back by
// shift_s), its gap mask, and (with a shift) its bins as tagged.
struct RecordBins {
  BinnedImu binned;
  std::optional<BinnedImu> as_tagged;
  std::vector<char> gaps;
};

RecordBins binRecording(const ImuRecording& rec, const GridSpec& grid, double shift_s = 0.0) {
  StreamedBinning y(grid);
  std::optional<StreamedBinning> y0;
  if (shift_s != 0.0) y0.emplace(grid);
  const bool gaps_possible = rec.samples >= 3 && grid.count > 0;
  GapMask gaps(grid, gaps_possible ? medianSampleInterval(rec) : 0.0);
  rec.pass([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      ImuSample moved = s;
      moved.t_s -= shift_s;
      y.add(moved);
      if (gaps_possible) gaps.add(moved);
      if (y0) y0->add(s);
    }
  });
  RecordBins out{y.finish(), std::nullopt, gaps.mask()};
  if (y0) out.as_tagged = y0->finish();
  return out;
}

}  // namespace

ResidualBins binResidual(const DiagnosisInputs& in, const ImuRecording& simulated,
                         const TimeAlignment& alignment, const GridSpec& grid,
                         DiagnosisResult* out) {
  const int n = grid.count;
  ResidualBins b;
  b.grid = grid;
  b.x = binImu(in.reference, grid);
  RecordBins sim = binRecording(simulated, grid);
  b.s = std::move(sim.binned);
  RecordBins real = binRecording(alignment.as_tagged, grid, alignment.realign_s);
  b.y = std::move(real.binned);
  b.r.resize(n, kMismatchChannels);
  b.r << b.y.omega_rad_s - b.s.omega_rad_s, b.y.f_m_s2 - b.s.f_m_s2;
  out->residual_before = b.r;
  // Bins overlapping a sampling gap (lost samples) of any record carry a wrong mean rate: they
  // are left out of every fit and RMS (residual and regressors zero there) and listed. The joint
  // fit's shifted reference is not masked; a few bins pull tau negligibly.
  maskSamplingGaps(
      {binsOverlappingGaps(in.reference, grid), std::move(sim.gaps), std::move(real.gaps)}, grid,
      out);
  zeroMaskedRows(out->masked_bins, &b.r);
  // With a realignment: the residual of the record as tagged (signal_rms_raw; the evidence of
  // the realignment when its remainder is not claimed).
  if (real.as_tagged) {
    const BinnedImu& y0 = *real.as_tagged;
    b.r0.resize(n, kMismatchChannels);
    b.r0 << y0.omega_rad_s - b.s.omega_rad_s, y0.f_m_s2 - b.s.f_m_s2;
    zeroMaskedRows(out->masked_bins, &b.r0);
  }
  return b;
}

}  // namespace graftnav::diagnosis_detail
