#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/mismatch/time_offset.h"

#include "graftnav/mismatch/streamed_binning.h"

namespace graftnav {

void TimeOffsetOptions::validate() const {
  if (!(bin_s > 0.0))
    throw std::invalid_argument("TimeOffsetOptions: bin_s = " + std::to_string(bin_s) +
                                " must be > 0");
  if (!(max_offset_s >= bin_s))
    throw std::invalid_argument(
        "TimeOffsetOptions: max_offset_s = " + std::to_string(max_offset_s) + " must be >= bin_s");
  if (!(coarse_bin_s > 0.0))
    throw std::invalid_argument(
        "TimeOffsetOptions: coarse_bin_s = " + std::to_string(coarse_bin_s) + " must be > 0");
}

namespace {

// The mean-removed angular rates of two records binned on one grid of bin_s.
struct CenteredRates {
  Eigen::MatrixX3d x, y;
  double bin_s = 0.0;
};

// The rates of one record on the grid, centred in place: only they are made of its bins (the
// fine grid has 100 bins a second; the specific force, temperature and vibration are not binned).
Eigen::MatrixX3d centeredRate(const ImuRecording& imu, const GridSpec& grid) {
  StreamedBinning binning(grid, 0.0, {}, BinnedColumns::rates_only);
  imu.pass([&binning](const ImuSeries& block) { binning.add(block); });
  Eigen::MatrixX3d w = std::move(binning.finish().omega_rad_s);
  const Eigen::RowVector3d mean = w.colwise().mean();
  w.rowwise() -= mean;
  return w;
}

CenteredRates centeredRates(const ImuRecording& reference, const ImuRecording& tested,
                            double bin_s) {
  const GridSpec grid = commonGrid(reference, tested, bin_s);
  CenteredRates rates;
  rates.x = centeredRate(reference, grid);
  rates.y = centeredRate(tested, grid);
  rates.bin_s = bin_s;
  return rates;
}

// Normalized cross-correlation of the centred rates at integer lags center - half .. center +
// half (bins); the best lag refined by a parabola.
struct CorrelationPeak {
  double lag_bins = 0.0;
  double correlation = 0.0;
  bool interior = false;
};

CorrelationPeak correlationPeak(const CenteredRates& rates, int center, int half) {
  const Eigen::MatrixX3d& xc = rates.x;
  const Eigen::MatrixX3d& yc = rates.y;
  const int n = static_cast<int>(xc.rows());
  const int extent = std::abs(center) + half;
  if (n < 4 * extent + 10)
    throw std::invalid_argument(
        "estimateTimeOffset: overlap of " + std::to_string(n * rates.bin_s) +
        " s is too short for a search out to " + std::to_string(extent * rates.bin_s) + " s");
  // c(L) = sum_t x(t) y(t + L) over the rows where both exist, normalized.
  const int lags = 2 * half + 1;
  Eigen::VectorXd corr(lags);
  for (int li = 0; li < lags; ++li) {
    const int L = center + li - half;
    const int i0 = std::max(0, -L), i1 = std::min(n, n - L);
    const int len = i1 - i0;
    const auto xs = xc.middleRows(i0, len);
    const auto ys = yc.middleRows(i0 + L, len);
    const double sxy = (xs.array() * ys.array()).sum();
    const double sxx = xs.squaredNorm(), syy = ys.squaredNorm();
    corr(li) = (sxx > 0.0 && syy > 0.0) ? sxy / std::sqrt(sxx * syy) : 0.0;
  }
  Eigen::Index best = 0;
  corr.maxCoeff(&best);
  CorrelationPeak peak;
  peak.correlation = corr(best);
  peak.interior = best > 0 && best < lags - 1;
  double frac = 0.0;
  if (peak.interior) {
    const double cm = corr(best - 1), c0 = corr(best), cp = corr(best + 1);
    const double den = cm - 2.0 * c0 + cp;
    if (den < 0.0) frac = std::clamp(0.5 * (cm - cp) / den, -0.5, 0.5);
  }
  peak.lag_bins = center + static_cast<double>(best - half) + frac;
  return peak;
}

}  // namespace

TimeOffsetEstimate estimateTimeOffset(const ImuSeries& reference, const ImuSeries& tested,
                                      const TimeOffsetOptions& options) {
  options.validate();
  if (reference.empty() || tested.empty())
    throw std::invalid_argument("estimateTimeOffset: empty IMU series");
  return estimateTimeOffset(viewedRecording(reference), viewedRecording(tested), options);
}

TimeOffsetEstimate estimateTimeOffset(const ImuRecording& reference, const ImuRecording& tested,
                                      const TimeOffsetOptions& options) {
  options.validate();
  const double overlap_s = std::min(reference.last.t_s, tested.last.t_s) -
                           std::max(reference.beginTime_s(), tested.beginTime_s());
  // Coarse stage: a wide search on coarse bins, capped at a quarter of the overlap.
  double center_s = 0.0;
  const double coarse_range_s = std::min(options.coarse_max_offset_s, 0.25 * overlap_s - 1.0);
  if (coarse_range_s > options.max_offset_s) {
    const int half = static_cast<int>(std::ceil(coarse_range_s / options.coarse_bin_s));
    const CorrelationPeak coarse =
        correlationPeak(centeredRates(reference, tested, options.coarse_bin_s), 0, half);
    if (coarse.interior && coarse.correlation >= options.min_correlation)
      center_s = coarse.lag_bins * options.coarse_bin_s;
  }
  // Fine stage around zero and, when the coarse peak lies elsewhere, around it: the higher
  // correlation wins (so a coarse stage can only help).
  const int half = static_cast<int>(std::ceil(options.max_offset_s / options.bin_s));
  const CenteredRates rates = centeredRates(reference, tested, options.bin_s);
  CorrelationPeak fine = correlationPeak(rates, 0, half);
  const int center = static_cast<int>(std::lround(center_s / options.bin_s));
  if (std::abs(center) > half / 2) {
    const CorrelationPeak far = correlationPeak(rates, center, half);
    if (far.correlation > fine.correlation) fine = far;
  }
  TimeOffsetEstimate est;
  est.peak_correlation = fine.correlation;
  est.tau_s = fine.lag_bins * options.bin_s;
  est.reliable = fine.interior && est.peak_correlation >= options.min_correlation;
  return est;
}

Eigen::MatrixXd timeOffsetRegressor(const ImuSeries& reference, const GridSpec& grid,
                                    double pivot_s, const ImuSampleMap& response) {
  const BinnedImu x = binImu(reference, grid, 0.0, response);
  const int n = grid.count;
  Eigen::MatrixXd xs(n, 6);
  xs << x.omega_rad_s, x.f_m_s2;
  Eigen::MatrixXd u(n, 6);
  if (pivot_s != 0.0) {
    // Bin (a, b] of x(t - pivot) = integral of x over (a - pivot, b - pivot].
    const BinnedImu shifted = binImu(reference, grid, -pivot_s, response);
    Eigen::MatrixXd ss(n, 6);
    ss << shifted.omega_rad_s, shifted.f_m_s2;
    u = (ss - xs) / pivot_s;
  } else {
    for (int i = 0; i < n; ++i) {
      const int a = std::max(0, i - 1), b = std::min(n - 1, i + 1);
      u.row(i) = -(xs.row(b) - xs.row(a)) / ((b - a) * grid.bin_s);
    }
  }
  return u;
}

}  // namespace graftnav
