#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/core/mismatch/time_offset.h"

namespace graftnav {

void TimeOffsetOptions::validate() const {
  if (!(bin_s > 0.0))
    throw std::invalid_argument("TimeOffsetOptions: bin_s = " + std::to_string(bin_s) +
                                " must be > 0");
  if (!(max_offset_s >= bin_s))
    throw std::invalid_argument("TimeOffsetOptions: max_offset_s = " +
                                std::to_string(max_offset_s) + " must be >= bin_s");
}

TimeOffsetEstimate estimateTimeOffset(const ImuSeries& reference, const ImuSeries& tested,
                                      const TimeOffsetOptions& options) {
  options.validate();
  const GridSpec grid = commonGrid(reference, tested, options.bin_s);
  const int max_lag = static_cast<int>(std::ceil(options.max_offset_s / options.bin_s));
  if (grid.count < 4 * max_lag + 10)
    throw std::invalid_argument("estimateTimeOffset: overlap of " +
                                std::to_string(grid.count * grid.bin_s) +
                                " s is too short for a search range of " +
                                std::to_string(options.max_offset_s) + " s");
  const BinnedImu x = binImu(reference, grid);
  const BinnedImu y = binImu(tested, grid);
  Eigen::MatrixX3d xc = x.omega_rad_s.rowwise() - x.omega_rad_s.colwise().mean();
  Eigen::MatrixX3d yc = y.omega_rad_s.rowwise() - y.omega_rad_s.colwise().mean();
  const int n = grid.count;
  // c(L) = sum_t x(t) y(t + L) over the rows where both exist, normalized.
  const int lags = 2 * max_lag + 1;
  Eigen::VectorXd corr(lags);
  for (int li = 0; li < lags; ++li) {
    const int L = li - max_lag;
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
  TimeOffsetEstimate est;
  est.peak_correlation = corr(best);
  double frac = 0.0;
  const bool interior = best > 0 && best < lags - 1;
  if (interior) {
    const double cm = corr(best - 1), c0 = corr(best), cp = corr(best + 1);
    const double den = cm - 2.0 * c0 + cp;
    if (den < 0.0) frac = std::clamp(0.5 * (cm - cp) / den, -0.5, 0.5);
  }
  est.tau_s = (static_cast<double>(best - max_lag) + frac) * options.bin_s;
  est.reliable = interior && est.peak_correlation >= options.min_correlation;
  return est;
}

Eigen::MatrixXd timeOffsetRegressor(const ImuSeries& reference, const GridSpec& grid,
                                    double pivot_s) {
  const BinnedImu x = binImu(reference, grid);
  const int n = grid.count;
  Eigen::MatrixXd xs(n, 6);
  xs << x.omega_rad_s, x.f_m_s2;
  Eigen::MatrixXd u(n, 6);
  if (pivot_s != 0.0) {
    // Bin (a, b] of x(t - pivot) = integral of x over (a - pivot, b - pivot].
    const BinnedImu shifted = binImu(reference, grid, -pivot_s);
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
