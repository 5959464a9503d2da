#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "graftnav/mismatch/common_grid.h"

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

std::size_t CumulativeImu::segment(double t_s) const {
  // Index k with t_[k] <= t < t_[k+1], clamped to the first/last segment.
  auto it = std::upper_bound(t_.begin(), t_.end(), t_s);
  std::size_t k = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  return std::min(k, t_.size() - 2);
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

// Node slopes of the cumulative integral: 5-point derivative where the four neighbouring
// intervals are equal (to 1e-6), else 3-point; the adjacent sample's rate at the ends. Computed
// when asked rather than stored (48 bytes a sample).
Vector6d CumulativeImu::slope(std::size_t k) const {
  const std::size_t N = t_.size();
  if (k == 0 || k + 1 == N) {
    const std::size_t a = k == 0 ? 0 : k - 1;
    return (cum_[a + 1] - cum_[a]) / (t_[a + 1] - t_[a]);
  }
  if (k >= 2 && k + 2 < N) {
    const double d = t_[k + 1] - t_[k];
    bool uniform = true;
    for (std::size_t j = k - 2; j < k + 2; ++j)
      uniform &= std::abs((t_[j + 1] - t_[j]) - d) <= 1e-6 * d;
    return uniform ? Vector6d((cum_[k - 2] - 8.0 * cum_[k - 1] + 8.0 * cum_[k + 1] - cum_[k + 2]) /
                              (12.0 * d))
                   : Vector6d((cum_[k + 1] - cum_[k - 1]) / (t_[k + 1] - t_[k - 1]));
  }
  return (cum_[k + 1] - cum_[k - 1]) / (t_[k + 1] - t_[k - 1]);
}

namespace {

// Kaiser-windowed sinc (half width kSincHalfWidth samples, beta 12.3) tabulated over the
// fraction u in [0, 1] of a sample, for the taps m = 1 - kSincHalfWidth .. kSincHalfWidth: weight
// of node k + m at position k + u. Kaiser's design rule for this length and beta: passband
// ripple ~1e-6 up to 0.44 x the sample rate. Until 2026-11-24 it was 32 taps at beta 8 (ripple
// ~1e-4): a 3-Hz road oscillation shifted by 4 ms came out 6.7e-5 too large, which against a
// common-random-numbers simulation showed as a -40..-60 ppm gyro scale factor next to every
// time offset (test MismatchGrid.ShiftedBinMeansKeepTheirGain).
constexpr int kSincHalfWidth = 32;
constexpr int kSincTable = 512;

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

}  // namespace

Vector6d CumulativeImu::at(double t_s) const {
  if (t_.size() < 2) return Vector6d::Zero();
  if (t_s <= t_.front()) return cum_.front() + (t_s - t_.front()) * slope(0);
  if (t_s >= t_.back()) return cum_.back() + (t_s - t_.back()) * slope(t_.size() - 1);
  const std::size_t k = segment(t_s);
  const double L = t_[k + 1] - t_[k];
  if (k >= kSincHalfWidth - 1 && k + kSincHalfWidth < t_.size() &&
      irregular_[k + kSincHalfWidth] == irregular_[k + 1 - kSincHalfWidth]) {
    // Uniform neighbourhood: band-limited interpolation of the integral's departure from the
    // chord through nodes k and k + 1 (Kaiser-windowed sinc over 64 nodes). Cubic Hermite loses
    // 0.4 % of a 15-Hz and 17 % of a 30-Hz component of a 0.05-s bin mean shifted by 14 ms at
    // 100 Hz; this keeps the gain of 0.3-42 Hz within 1e-5 (road and engine vibration reach
    // 40 Hz; a scale factor is resolved to ~1 ppm under common random numbers).
    const double u = (t_s - t_[k]) / L;
    const Vector6d chord = cum_[k + 1] - cum_[k];
    Vector6d out = cum_[k] + u * chord;
    const std::vector<double>& table = sincTable();
    const double pos = u * kSincTable;
    const int i = std::min(static_cast<int>(pos), kSincTable - 1);
    const double f = pos - i;
    const double* w0 = &table[i * 2 * kSincHalfWidth];
    const double* w1 = w0 + 2 * kSincHalfWidth;
    for (int j = 0; j < 2 * kSincHalfWidth; ++j) {
      const int m = j + 1 - kSincHalfWidth;
      if (m == 0 || m == 1) continue;  // the chord's own nodes: zero departure
      const Vector6d d = cum_[k + m] - cum_[k] - m * chord;
      out += ((1.0 - f) * w0[j] + f * w1[j]) * d;
    }
    return out;
  }
  const double s = (t_s - t_[k]) / L, s2 = s * s, s3 = s2 * s;
  return (2.0 * s3 - 3.0 * s2 + 1.0) * cum_[k] + (s3 - 2.0 * s2 + s) * L * slope(k) +
         (-2.0 * s3 + 3.0 * s2) * cum_[k + 1] + (s3 - s2) * L * slope(k + 1);
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
  const std::size_t k = segment(t_s);
  const double w = (t_s - t_[k]) / (t_[k + 1] - t_[k]);
  return cum_temp_[k] + w * (cum_temp_[k + 1] - cum_temp_[k]);
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
  const CumulativeImu cum(imu, map);
  BinnedImu out;
  out.grid = grid;
  const int n = grid.count;
  out.omega_rad_s.resize(n, 3);
  out.f_m_s2.resize(n, 3);
  out.temperature_degC.setConstant(n, std::numeric_limits<double>::quiet_NaN());
  out.f_within_rms_m_s2.setZero(n);
  Vector6d prev = cum.at(grid.binStart(0) + time_shift_s);
  double prev_temp = cum.temperatureIntegralAt(grid.binStart(0) + time_shift_s);
  for (int i = 0; i < n; ++i) {
    const double t_end = grid.binStart(i + 1) + time_shift_s;
    const Vector6d next = cum.at(t_end);
    const Vector6d mean = (next - prev) / grid.bin_s;
    out.omega_rad_s.row(i) = mean.head<3>().transpose();
    out.f_m_s2.row(i) = mean.tail<3>().transpose();
    if (cum.hasTemperature()) {
      const double next_temp = cum.temperatureIntegralAt(t_end);
      out.temperature_degC(i) = (next_temp - prev_temp) / grid.bin_s;
      prev_temp = next_temp;
    }
    prev = next;
  }
  // Within-bin vibration: samples whose end tag falls inside a (shifted) bin.
  Eigen::VectorXd sum_sq = Eigen::VectorXd::Zero(n);
  Eigen::VectorXi count = Eigen::VectorXi::Zero(n);
  for (const ImuSample& raw : imu) {
    const int i =
        static_cast<int>(std::floor((raw.t_s - time_shift_s - grid.t_begin_s) / grid.bin_s));
    if (i < 0 || i >= n || !(raw.dt_s > 0.0)) continue;
    const Eigen::Vector3d f = (map ? map(raw) : raw).dvel_m_s / raw.dt_s;
    sum_sq(i) += (f - out.f_m_s2.row(i).transpose()).squaredNorm();
    ++count(i);
  }
  for (int i = 0; i < n; ++i)
    out.f_within_rms_m_s2(i) = count(i) > 0 ? std::sqrt(sum_sq(i) / count(i)) : 0.0;
  return out;
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
  if (imu.empty()) return 0.0;
  std::vector<double> dt;
  dt.reserve(imu.size());
  for (const ImuSample& s : imu) dt.push_back(s.dt_s);
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

std::vector<char> binsOverlappingGaps(const ImuSeries& imu, const GridSpec& grid,
                                      double gap_factor) {
  std::vector<char> mask(std::max(0, grid.count), 0);
  if (imu.size() < 3 || grid.count <= 0) return mask;
  const double limit = gap_factor * medianSampleInterval(imu);
  for (const ImuSample& s : imu) {
    if (!(s.dt_s > limit)) continue;
    const double a = (s.t_s - s.dt_s - grid.t_begin_s) / grid.bin_s;
    const double b = (s.t_s - grid.t_begin_s) / grid.bin_s;
    const int i0 = std::max(0, static_cast<int>(std::floor(a)) - 1);
    const int i1 = std::min(grid.count - 1, static_cast<int>(std::ceil(b)));
    for (int i = i0; i <= i1; ++i) mask[i] = 1;
  }
  return mask;
}

}  // namespace graftnav
