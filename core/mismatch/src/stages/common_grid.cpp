#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "graftnav/mismatch/common_grid.h"

#include "cumulative_nodes.h"
#include "graftnav/mismatch/streamed_binning.h"

namespace graftnav {

CumulativeImu::CumulativeImu(const ImuSeries& imu, const ImuSampleMap& map) {
  if (imu.empty()) throw std::invalid_argument("CumulativeImu: empty IMU series");
  has_temperature_ =
      std::all_of(imu.begin(), imu.end(), [](const ImuSample& s) { return s.hasTemperature(); });
  t_.reserve(imu.size() + 1);
  cum_.reserve(imu.size() + 1);
  t_.push_back(imu.front().t_s - imu.front().dt_s);
  cum_.push_back(Vector6d::Zero());
  if (has_temperature_) cum_temp_.reserve(imu.size() + 1);
  if (has_temperature_) cum_temp_.push_back(0.0);  // else not stored (temperatureIntegralAt: NaN)
  for (std::size_t k = 0; k < imu.size(); ++k) {
    const ImuSample s = map ? map(imu[k]) : imu[k];
    if (!(s.dt_s > 0.0))
      throw std::invalid_argument("CumulativeImu: sample " + std::to_string(k) +
                                  " has dt_s = " + std::to_string(s.dt_s) + " (must be > 0)");
    // Boundaries follow the time tags; a gap or overlap between samples is absorbed by using the
    // tag as the end and the previous end as the start (the increment is spread over it).
    const double t_end = s.t_s;
    if (!(t_end > t_.back()))
      throw std::invalid_argument("CumulativeImu: sample " + std::to_string(k) + " at t = " +
                                  std::to_string(t_end) + " is not after the previous sample");
    Vector6d inc;
    inc << s.dtheta_rad, s.dvel_m_s;
    t_.push_back(t_end);
    cum_.push_back(cum_.back() + inc);
    if (has_temperature_)
      cum_temp_.push_back(cum_temp_.back() + s.temperature_degC * (t_end - t_[t_.size() - 2]));
  }
  computeIrregular();
}

// CumulativeImu's arrays as the node store of the interpolation (cumulative_nodes.h).
struct CumulativeImu::NodeView {
  const CumulativeImu& c;
  std::size_t size() const { return c.t_.size(); }
  double t(std::size_t k) const { return c.t_[k]; }
  const Vector6d& cum(std::size_t k) const { return c.cum_[k]; }
  double cumTemp(std::size_t k) const { return c.cum_temp_[k]; }
  int irregular(std::size_t k) const { return c.irregular_[k]; }
  std::size_t upperBound(double t_s) const {
    return static_cast<std::size_t>(std::upper_bound(c.t_.begin(), c.t_.end(), t_s) - c.t_.begin());
  }
};

std::size_t CumulativeImu::segment(double t_s) const {
  return grid_detail::segment(NodeView{*this}, t_s);
}

void CumulativeImu::computeIrregular() {
  // irregular_[k]: intervals before node k that differ from their predecessor by more than 1e-6
  // (a prefix count: a window of nodes is uniform when the count does not change across it).
  irregular_.assign(t_.size(), 0);
  for (std::size_t k = 2; k < t_.size(); ++k) {
    const double d = t_[k] - t_[k - 1], d0 = t_[k - 1] - t_[k - 2];
    irregular_[k] = irregular_[k - 1] + (std::abs(d - d0) > 1e-6 * d0 ? 1 : 0);
  }
}

Vector6d CumulativeImu::slope(std::size_t k) const {
  return grid_detail::slope(NodeView{*this}, k);
}

namespace grid_detail {

// Kaiser-windowed sinc (half width kSincHalfWidth samples, beta 12.3) tabulated over the
// fraction u in [0, 1] of a sample, for the taps m = 1 - kSincHalfWidth .. kSincHalfWidth: weight
// of node k + m at position k + u. Kaiser's design rule for this length and beta: passband
// ripple ~1e-6 up to 0.44 x the sample rate. Until 2026-11-24 it was 32 taps at beta 8 (ripple
// ~1e-4): a 3-Hz road oscillation shifted by 4 ms came out 6.7e-5 too large, which against a
// common-random-numbers simulation showed as a -40..-60 ppm gyro scale factor next to every
// time offset (test MismatchGrid.ShiftedBinMeansKeepTheirGain).
const std::vector<double>& sincTable() {
  static const std::vector<double> table = [] {
    const double beta = 12.3, i0 = std::cyl_bessel_i(0.0, beta);
    std::vector<double> t((kSincTable + 1) * 2 * kSincHalfWidth);
    for (int i = 0; i <= kSincTable; ++i) {
      const double u = static_cast<double>(i) / kSincTable;
      for (int j = 0; j < 2 * kSincHalfWidth; ++j) {
        const double z = u - (j + 1 - kSincHalfWidth);
        const double x = M_PI * z;
        const double sinc = std::abs(z) < 1e-12 ? 1.0 : std::sin(x) / x;
        const double r = z / kSincHalfWidth;
        const double win =
            std::cyl_bessel_i(0.0, beta * std::sqrt(std::max(0.0, 1.0 - r * r))) / i0;
        t[i * 2 * kSincHalfWidth + j] = sinc * win;
      }
    }
    return t;
  }();
  return table;
}

}  // namespace grid_detail

Vector6d CumulativeImu::at(double t_s) const {
  return grid_detail::integralAt(NodeView{*this}, t_s);
}

Vector6d CumulativeImu::rateAt(double t_s) const {
  if (t_.size() < 2) return Vector6d::Zero();
  if (t_s <= t_.front()) return slope(0);
  if (t_s >= t_.back()) return slope(t_.size() - 1);
  const std::size_t k = segment(t_s);
  const double L = t_[k + 1] - t_[k];
  const double s = (t_s - t_[k]) / L, s2 = s * s;
  return ((6.0 * s2 - 6.0 * s) * (cum_[k] - cum_[k + 1])) / L +
         (3.0 * s2 - 4.0 * s + 1.0) * slope(k) + (3.0 * s2 - 2.0 * s) * slope(k + 1);
}

double CumulativeImu::temperatureIntegralAt(double t_s) const {
  if (!has_temperature_) return std::numeric_limits<double>::quiet_NaN();
  return grid_detail::temperatureIntegralAt(NodeView{*this}, t_s);
}

GridSpec commonGrid(const ImuRecording& a, const ImuRecording& b, double bin_s, double margin_s) {
  if (a.samples == 0 || b.samples == 0)
    throw std::invalid_argument("commonGrid: empty IMU recording");
  return commonGrid(a.span(), b.span(), bin_s, margin_s);
}

GridSpec commonGrid(const ImuSeries& a, const ImuSeries& b, double bin_s, double margin_s) {
  if (!(bin_s > 0.0)) throw std::invalid_argument("commonGrid: bin_s must be > 0");
  if (a.empty() || b.empty()) throw std::invalid_argument("commonGrid: empty IMU series");
  const double t0 = std::max(a.front().t_s - a.front().dt_s, b.front().t_s - b.front().dt_s) +
                    std::max(0.0, margin_s);
  const double t1 = std::min(a.back().t_s, b.back().t_s) - std::max(0.0, margin_s);
  GridSpec g;
  g.t_begin_s = t0;
  g.bin_s = bin_s;
  g.count = static_cast<int>(std::floor((t1 - t0) / bin_s + 1e-9));
  if (g.count < 10)
    throw std::invalid_argument("commonGrid: the two records overlap by " +
                                std::to_string(t1 - t0) + " s, fewer than 10 bins of " +
                                std::to_string(bin_s) + " s");
  return g;
}

BinnedImu binImu(const ImuSeries& imu, const GridSpec& grid, double time_shift_s,
                 const ImuSampleMap& map) {
  StreamedBinning binning(grid, time_shift_s, map);
  binning.add(imu);
  return binning.finish();
}

EvenPowerBins binEvenPowers(const ImuSeries& imu, const GridSpec& grid, double time_shift_s) {
  // Per sample: the rate's even function times the sample's length (a sample without a length
  // is left as it is, as binImu skips it).
  const auto even = [](auto power) {
    return [power](const ImuSample& smp) {
      ImuSample out = smp;
      const double dt = smp.dt_s;
      if (!(dt > 0.0)) return out;
      const Eigen::Vector3d w = smp.dtheta_rad / dt, f = smp.dvel_m_s / dt;
      out.dtheta_rad = power(w) * dt;
      out.dvel_m_s = power(f) * dt;
      return out;
    };
  };
  const BinnedImu a =
      binImu(imu, grid, time_shift_s, even([](const Eigen::Vector3d& x) { return x.cwiseAbs(); }));
  const BinnedImu q =
      binImu(imu, grid, time_shift_s, even([](const Eigen::Vector3d& x) { return x.cwiseAbs2(); }));
  return {a.omega_rad_s, a.f_m_s2, q.omega_rad_s, q.f_m_s2};
}

double medianSampleInterval(const ImuSeries& imu) {
  return imu.empty() ? 0.0 : medianSampleInterval(viewedRecording(imu));
}

double medianSampleInterval(const ImuRecording& imu) {
  if (imu.samples == 0) return 0.0;
  std::map<double, std::size_t> count;  // the nth_element of the sorted intervals, n = size / 2
  std::size_t n = 0;
  imu.pass([&](const ImuSeries& block) {
    for (const ImuSample& s : block) ++count[s.dt_s];
    n += block.size();
  });
  std::size_t below = 0;
  for (const auto& [dt, k] : count) {
    below += k;
    if (below > n / 2) return dt;
  }
  return 0.0;
}

GapMask::GapMask(const GridSpec& grid, double median_interval_s, double gap_factor)
    : grid_(grid), limit_s_(gap_factor * median_interval_s), mask_(std::max(0, grid.count), 0) {}

void GapMask::add(const ImuSample& s) {
  if (!(s.dt_s > limit_s_) || grid_.count <= 0) return;
  const double a = (s.t_s - s.dt_s - grid_.t_begin_s) / grid_.bin_s;
  const double b = (s.t_s - grid_.t_begin_s) / grid_.bin_s;
  const int i0 = std::max(0, static_cast<int>(std::floor(a)) - 1);
  const int i1 = std::min(grid_.count - 1, static_cast<int>(std::ceil(b)));
  for (int i = i0; i <= i1; ++i) mask_[i] = 1;
}

std::vector<char> binsOverlappingGaps(const ImuSeries& imu, const GridSpec& grid,
                                      double gap_factor) {
  if (imu.size() < 3 || grid.count <= 0) return std::vector<char>(std::max(0, grid.count), 0);
  GapMask gaps(grid, medianSampleInterval(imu), gap_factor);
  gaps.add(imu);
  return gaps.mask();
}

}  // namespace graftnav
