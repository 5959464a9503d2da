#pragma once
// The interpolation of a cumulative IMU integral between its nodes (CumulativeImu::at, its
// slopes and its temperature integral), written once over any store of nodes: CumulativeImu's
// arrays over the whole record and StreamedBinning's window of the nodes read so far. `Nodes`
// provides size() (the node count), t(k), cum(k), cumTemp(k), irregular(k) and upperBound(t_s)
// (the index of the first node after t_s); a window answers only for the nodes it holds, and
// its caller evaluates where those are all the formulas read (StreamedBinning::integralAt).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "graftnav/mismatch/common_grid.h"

namespace graftnav::grid_detail {

// Kaiser-windowed sinc taps (common_grid.cpp): half width in samples and table resolution.
inline constexpr int kSincHalfWidth = 32;
inline constexpr int kSincTable = 512;
const std::vector<double>& sincTable();

// Index k with t(k) <= t < t(k+1), clamped to the first/last segment.
template <class Nodes>
std::size_t segment(const Nodes& n, double t_s) {
  const std::size_t ub = n.upperBound(t_s);
  const std::size_t k = ub == 0 ? 0 : ub - 1;
  return std::min(k, n.size() - 2);
}

// Node slopes of the cumulative integral: 5-point derivative where the four neighbouring
// intervals are equal (to 1e-6), else 3-point; the adjacent sample's rate at the ends. Computed
// when asked rather than stored (48 bytes a sample).
template <class Nodes>
Vector6d slope(const Nodes& n, std::size_t k) {
  const std::size_t N = n.size();
  if (k == 0 || k + 1 == N) {
    const std::size_t a = k == 0 ? 0 : k - 1;
    return (n.cum(a + 1) - n.cum(a)) / (n.t(a + 1) - n.t(a));
  }
  if (k >= 2 && k + 2 < N) {
    const double d = n.t(k + 1) - n.t(k);
    bool uniform = true;
    for (std::size_t j = k - 2; j < k + 2; ++j)
      uniform &= std::abs((n.t(j + 1) - n.t(j)) - d) <= 1e-6 * d;
    return uniform
               ? Vector6d((n.cum(k - 2) - 8.0 * n.cum(k - 1) + 8.0 * n.cum(k + 1) - n.cum(k + 2)) /
                          (12.0 * d))
               : Vector6d((n.cum(k + 1) - n.cum(k - 1)) / (n.t(k + 1) - n.t(k - 1)));
  }
  return (n.cum(k + 1) - n.cum(k - 1)) / (n.t(k + 1) - n.t(k - 1));
}

// CumulativeImu::at (common_grid.h): band-limited between uniform nodes, else cubic Hermite.
template <class Nodes>
Vector6d integralAt(const Nodes& n, double t_s) {
  const std::size_t N = n.size();
  if (N < 2) return Vector6d::Zero();
  if (t_s <= n.t(0)) return n.cum(0) + (t_s - n.t(0)) * slope(n, 0);
  if (t_s >= n.t(N - 1)) return n.cum(N - 1) + (t_s - n.t(N - 1)) * slope(n, N - 1);
  const std::size_t k = segment(n, t_s);
  const double L = n.t(k + 1) - n.t(k);
  if (k >= kSincHalfWidth - 1 && k + kSincHalfWidth < N &&
      n.irregular(k + kSincHalfWidth) == n.irregular(k + 1 - kSincHalfWidth)) {
    // Uniform neighbourhood: band-limited interpolation of the integral's departure from the
    // chord through nodes k and k + 1 (Kaiser-windowed sinc over 64 nodes). Cubic Hermite loses
    // 0.4 % of a 15-Hz and 17 % of a 30-Hz component of a 0.05-s bin mean shifted by 14 ms at
    // 100 Hz; this keeps the gain of 0.3-42 Hz within 1e-5 (road and engine vibration reach
    // 40 Hz; a scale factor is resolved to ~1 ppm under common random numbers).
    const double u = (t_s - n.t(k)) / L;
    const Vector6d chord = n.cum(k + 1) - n.cum(k);
    Vector6d out = n.cum(k) + u * chord;
    const std::vector<double>& table = sincTable();
    const double pos = u * kSincTable;
    const int i = std::min(static_cast<int>(pos), kSincTable - 1);
    const double f = pos - i;
    const double* w0 = &table[i * 2 * kSincHalfWidth];
    const double* w1 = w0 + 2 * kSincHalfWidth;
    for (int j = 0; j < 2 * kSincHalfWidth; ++j) {
      const int m = j + 1 - kSincHalfWidth;
      if (m == 0 || m == 1) continue;  // the chord's own nodes: zero departure
      const Vector6d d = n.cum(k + m) - n.cum(k) - m * chord;
      out += ((1.0 - f) * w0[j] + f * w1[j]) * d;
    }
    return out;
  }
  const double s = (t_s - n.t(k)) / L, s2 = s * s, s3 = s2 * s;
  return (2.0 * s3 - 3.0 * s2 + 1.0) * n.cum(k) + (s3 - 2.0 * s2 + s) * L * slope(n, k) +
         (-2.0 * s3 + 3.0 * s2) * n.cum(k + 1) + (s3 - s2) * L * slope(n, k + 1);
}

// CumulativeImu::temperatureIntegralAt without the check for a temperature.
template <class Nodes>
double temperatureIntegralAt(const Nodes& n, double t_s) {
  const std::size_t k = segment(n, t_s);
  const double w = (t_s - n.t(k)) / (n.t(k + 1) - n.t(k));
  return n.cumTemp(k) + w * (n.cumTemp(k + 1) - n.cumTemp(k));
}

}  // namespace graftnav::grid_detail
