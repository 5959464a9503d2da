#include "graftnav/sg/grafting.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <string>

namespace graftnav {
namespace {
using Vec6 = Eigen::Matrix<double, 6, 1>;

double evalPoly(const std::vector<double>& c, double x) {
  double y = 0.0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) y = y * x + *it;
  return y;
}
}  // namespace

namespace {
// D(x): the fitted dynamic error without its constant term.
Eigen::Vector3d dynamicPart(const SensorDynamicFit& f, const Eigen::Vector3d& x) {
  Eigen::Vector3d d;
  for (int i = 0; i < 3; ++i) {
    const auto& c = f.poly[i];
    d[i] = c.empty() ? 0.0 : evalPoly(c, x[i]) - c[0] - x[i];
  }
  if (f.use_cross_axis) {
    Eigen::Matrix3d off = f.M;
    off.diagonal().setZero();
    d += off * x;
  }
  return d;
}
}  // namespace

Eigen::Vector3d SensorDynamicFit::dynamicError(const Eigen::Vector3d& x) const {
  return dynamicPart(*this, x) - dynamicPart(*this, static_point);
}

BasicErrorSignal::BasicErrorSignal(const ImuSeries& e) {
  if (e.size() < 2) {
    throw std::invalid_argument(
        "BasicErrorSignal: the static error record needs at least 2 samples, got " +
        std::to_string(e.size()));
  }
  inc_.reserve(e.size());
  dt_.reserve(e.size());
  for (const ImuSample& s : e) {
    if (!(s.dt_s > 0.0)) {
      throw std::invalid_argument("BasicErrorSignal: sample at t=" + std::to_string(s.t_s) +
                                  " has non-positive dt " + std::to_string(s.dt_s));
    }
    Vec6 inc;
    inc << s.dtheta_rad, s.dvel_m_s;
    inc_.push_back(inc);
    dt_.push_back(s.dt_s);
  }
  count_ = inc_.size();
  addCheckpoints();
}

void BasicErrorSignal::addCheckpoints() {
  const std::size_t n = inc_.size();
  block_cum_.clear();
  block_tau_.clear();
  block_cum_.reserve(n / kBlock + 1);
  block_tau_.reserve(n / kBlock + 1);
  double tau = 0.0;
  Vec6 c = Vec6::Zero();
  for (std::size_t j = 0; j < n; ++j) {
    if (j % kBlock == 0) {
      block_tau_.push_back(tau);
      block_cum_.push_back(c);
    }
    tau += dt_[j];
    c += inc_[j];
  }
  total_ = c;
  record_length_s_ = tau;
}

double BasicErrorSignal::tauEnd(std::size_t j) const {
  const std::size_t b = j / kBlock;
  double tau = block_tau_[b];
  for (std::size_t i = b * kBlock; i <= j; ++i) tau += dt(i);
  return tau;
}

void BasicErrorSignal::readWindow(std::size_t j) const {
  if (!spool_ || j >= count_)
    throw std::out_of_range("BasicErrorSignal: sample " + std::to_string(j) + " of " +
                            std::to_string(count_));
  const std::size_t begin = j / kWindow * kWindow;
  const std::size_t n = std::min(kWindow, count_ - begin);
  inc_.resize(n);
  std::vector<double> column;
  for (int c = 0; c < 6; ++c) {
    spool_->read(c * count_ + begin, n, &column);
    for (std::size_t i = 0; i < n; ++i) inc_[i][c] = column[i];
  }
  spool_->read(6 * count_ + begin, n, &dt_);
  window_begin_ = begin;
}

std::size_t BasicErrorSignal::firstEndAtOrAfter(double tau_s) const {
  if (tau_s <= 0.0) return 0;
  // The last block that starts before tau_s holds the first sample ending at or after it.
  const auto it = std::lower_bound(block_tau_.begin(), block_tau_.end(), tau_s);
  const auto b = static_cast<std::size_t>(it - block_tau_.begin()) - 1;
  double tau = block_tau_[b];
  for (std::size_t j = b * kBlock; j < count_; ++j) {
    tau += dt(j);
    if (tau >= tau_s) return j;
  }
  return count_;
}

std::size_t BasicErrorSignal::firstEndAfter(double tau_s) const {
  if (tau_s < 0.0) return 0;
  const auto it = std::upper_bound(block_tau_.begin(), block_tau_.end(), tau_s);
  const auto b = static_cast<std::size_t>(it - block_tau_.begin()) - 1;
  double tau = block_tau_[b];
  for (std::size_t j = b * kBlock; j < count_; ++j) {
    tau += dt(j);
    if (tau > tau_s) return j;
  }
  return count_;
}

Eigen::Vector3d BasicErrorSignal::meanGyro_rad_s() const {
  return total_.head<3>() / record_length_s_;
}
Eigen::Vector3d BasicErrorSignal::meanAccel_m_s2() const {
  return total_.tail<3>() / record_length_s_;
}

Vec6 BasicErrorSignal::withinRecord(double tau) const {
  if (tau <= 0.0) return Vec6::Zero();
  if (tau >= record_length_s_) return total_;
  // First sample whose end is >= tau; the rate is constant inside it.
  const std::size_t j = firstEndAtOrAfter(tau);
  const std::size_t b = j / kBlock;
  double end = block_tau_[b];
  Vec6 cum = block_cum_[b];
  for (std::size_t i = b * kBlock; i <= j; ++i) {
    end += dt(i);
    cum += inc(i);
  }
  const Vec6 rate = inc(j) / dt(j);
  const double over = end - tau;  // part of sample j after tau
  return cum - rate * over;
}

Vec6 BasicErrorSignal::cumulative(double u) const {
  if (u <= 0.0) return Vec6::Zero();
  const double T = record_length_s_;
  const double m = std::floor(u / T);
  const double tau = u - m * T;
  const long tile = static_cast<long>(m);
  const Vec6 whole = total_;
  // Even tiles run forward, odd tiles run the record backwards in time.
  const Vec6 part = (tile % 2 == 0) ? withinRecord(tau) : Vec6(whole - withinRecord(T - tau));
  return m * whole + part;
}

Vec6 BasicErrorSignal::integral(double u0, double u1) const {
  return cumulative(u1) - cumulative(u0);
}

double BasicErrorSignal::sampleBoundaryAtOrBefore(double u) const {
  if (u <= 0.0) return 0.0;
  const double T = record_length_s_;
  const double m = std::floor(u / T);
  const double tau = u - m * T;
  const long tile = static_cast<long>(m);
  if (tile % 2 == 0) {
    // Forward tile: the last sample end at or before tau (sample starts are the previous ends).
    const std::size_t j = firstEndAfter(tau);
    const double b = j == 0 ? 0.0 : tauEnd(j - 1);
    return m * T + b;
  }
  // Mirrored tile: boundaries at T - tau_end_j; the largest one <= tau is T minus the smallest
  // tau_end_j >= T - tau.
  const std::size_t j = firstEndAtOrAfter(T - tau);
  const double b = j == count_ ? 0.0 : T - tauEnd(j);
  return m * T + std::max(0.0, b);
}

LabErrorRates BasicErrorSignal::rates() const {
  LabErrorRates r;
  r.dt_s = sampleLengths();
  r.rate.resize(count_);
  for (std::size_t j = 0; j < count_; ++j) r.rate[j] = inc(j) / dt(j);
  return r;
}

std::vector<double> BasicErrorSignal::sampleLengths() const {
  std::vector<double> length(count_);
  double start = 0.0;
  for (std::size_t j = 0; j < count_; ++j) {
    const double end = tauEnd(j);
    length[j] = end - start;
    start = end;
  }
  return length;
}

namespace {
double surrogateSampleLength(const std::vector<double>& length, std::size_t j) {
  const double dt = length[surrogateSample(length.size(), j)];
  if (!(dt > 0.0))
    throw std::invalid_argument("BasicErrorSignal: surrogate sample " + std::to_string(j) +
                                " has non-positive dt " + std::to_string(dt));
  return dt;
}
}  // namespace

BasicErrorSignal BasicErrorSignal::phaseRandomized(std::uint64_t seed,
                                                   const SlowNoiseModel* slow) const {
  const std::vector<double> length = sampleLengths();
  const std::size_t n = count_, m = surrogateLength(n);
  BasicErrorSignal out;
  out.count_ = m;
  out.inc_.assign(m, Vec6::Zero());
  out.dt_.resize(m);
  for (std::size_t j = 0; j < m; ++j) out.dt_[j] = surrogateSampleLength(length, j);
  // Each surrogate rate times its sample's length: the increment of the surrogate's sample.
  phaseRandomizedSurrogateChannels(
      n, [this](std::size_t j, int c) { return inc(j)[c] / dt(j); },
      [&length](std::size_t j) { return length[j]; }, seed, slow,
      [&out](int c, const std::vector<std::complex<double>>& rate) {
        for (std::size_t j = 0; j < rate.size(); ++j) out.inc_[j][c] = rate[j].real() * out.dt_[j];
      });
  out.addCheckpoints();
  return out;
}

BasicErrorSignal BasicErrorSignal::phaseRandomizedSpooled(std::uint64_t seed,
                                                          const SlowNoiseModel* slow,
                                                          const std::string& directory) const {
  const std::vector<double> length = sampleLengths();
  const std::size_t n = count_, m = surrogateLength(n);
  const std::size_t blocks = (m + kBlock - 1) / kBlock;
  BasicErrorSignal out;
  out.count_ = m;
  auto spool = std::make_shared<RecordSpool>(1, directory);
  // The running sums per channel in the order of addCheckpoints' running sum over samples (a
  // sum of six independent channels), so the checkpoints are the held surrogate's.
  out.block_cum_.assign(blocks, Vec6::Zero());
  phaseRandomizedSurrogateChannels(
      n, [this](std::size_t j, int c) { return inc(j)[c] / dt(j); },
      [&length](std::size_t j) { return length[j]; }, seed, slow,
      [&](int c, const std::vector<std::complex<double>>& rate) {
        std::vector<double> column(std::min(m, kWindow));
        double sum = 0.0;
        for (std::size_t begin = 0; begin < m; begin += column.size()) {
          const std::size_t count = std::min(column.size(), m - begin);
          for (std::size_t i = 0; i < count; ++i) {
            const std::size_t j = begin + i;
            if (j % kBlock == 0) out.block_cum_[j / kBlock][c] = sum;
            column[i] = rate[j].real() * length[surrogateSample(n, j)];
            sum += column[i];
          }
          spool->append(column.data(), count);
        }
        out.total_[c] = sum;
      });
  std::vector<double> column;
  column.reserve(std::min(m, kWindow));
  double tau = 0.0;
  out.block_tau_.reserve(blocks);
  for (std::size_t j = 0; j < m; ++j) {
    if (j % kBlock == 0) out.block_tau_.push_back(tau);
    column.push_back(surrogateSampleLength(length, j));
    tau += column.back();
    if (column.size() == kWindow || j + 1 == m) {
      spool->append(column.data(), column.size());
      column.clear();
    }
  }
  out.record_length_s_ = tau;
  spool->finish();
  out.spool_ = std::move(spool);
  return out;
}

double graftStartOffset(const GraftOptions& opt, const BasicErrorSignal& basic) {
  if (opt.start_offset_s >= 0.0) return opt.start_offset_s;
  std::mt19937_64 rng(opt.seed);
  std::uniform_int_distribution<std::size_t> j(0, basic.sampleCount() - 1);
  return basic.sampleStart_s(j(rng));
}

GraftSignal::GraftSignal(const BasicErrorSignal& record, const GraftOptions& opt)
    : power_on_(opt.power_on) {
  if (opt.surrogate_seed) {
    const SlowNoiseModel* slow = opt.surrogate_slow_noise ? &*opt.surrogate_slow_noise : nullptr;
    if (opt.spool_surrogate) {
      surrogate_.emplace(
          record.phaseRandomizedSpooled(*opt.surrogate_seed, slow, opt.spool_directory));
    } else {
      surrogate_.emplace(record.phaseRandomized(*opt.surrogate_seed, slow));
    }
  }
  basic_ = surrogate_ ? &*surrogate_ : &record;
  offset_s_ = graftStartOffset(opt, *basic_);
}

namespace {

// One grafted sample (SG#1 when `dynamic` adds nothing): what graftBasic and graftFull did for
// each sample of a whole series, so that a series grafted block by block is the same.
template <typename DynamicFn>
void graftSamples(const ImuSeries& ref, double t0, const BasicErrorSignal& basic, double offset,
                  const PowerOnErrors& power_on, DynamicFn&& dynamic, ImuSeries* out) {
  out->resize(ref.size());
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const ImuSample& r = ref[k];
    ImuSample& y = (*out)[k];
    y = r;
    const double u1 = r.t_s - t0 + offset;
    Vec6 e = basic.integral(u1 - r.dt_s, u1);
    if (!power_on.empty()) e += power_on.integral(r.t_s - t0 - r.dt_s, r.t_s - t0);
    Eigen::Vector3d dg, da;
    dynamic(r, dg, da);
    y.dtheta_rad = r.dtheta_rad + dg + e.head<3>();
    y.dvel_m_s = r.dvel_m_s + da + e.tail<3>();
  }
}

}  // namespace

void GraftSignal::graft(const ImuSeries& ref, double t0_s, const SensorDynamicFit* gyro,
                        const SensorDynamicFit* accel, ImuSeries* out) const {
  std::unique_lock<std::mutex> reading(read_mutex_, std::defer_lock);
  if (basic_->spooled()) reading.lock();
  if (gyro && accel) {
    graftSamples(
        ref, t0_s, *basic_, offset_s_, power_on_,
        [&](const ImuSample& r, Eigen::Vector3d& dg, Eigen::Vector3d& da) {
          // Fitting functions act on mean rates; convert back to increments.
          dg = gyro->dynamicError(r.dtheta_rad / r.dt_s) * r.dt_s;
          da = accel->dynamicError(r.dvel_m_s / r.dt_s) * r.dt_s;
        },
        out);
  } else {
    graftSamples(
        ref, t0_s, *basic_, offset_s_, power_on_,
        [](const ImuSample&, Eigen::Vector3d& dg, Eigen::Vector3d& da) {
          dg.setZero();
          da.setZero();
        },
        out);
  }
}

namespace {
ImuSeries graftWhole(const ImuSeries& ref, const BasicErrorSignal& basic,
                     const SensorDynamicFit* gyro, const SensorDynamicFit* accel,
                     const GraftOptions& opt) {
  ImuSeries out;
  if (ref.empty()) return out;
  // The tiling clock starts at the beginning of the first reference interval.
  GraftSignal(basic, opt).graft(ref, ref.front().t_s - ref.front().dt_s, gyro, accel, &out);
  return out;
}
}  // namespace

ImuSeries graftBasic(const ImuSeries& ref, const BasicErrorSignal& basic, const GraftOptions& opt) {
  return graftWhole(ref, basic, nullptr, nullptr, opt);
}

ImuSeries graftFull(const ImuSeries& ref, const BasicErrorSignal& basic,
                    const SensorDynamicFit& gyro, const SensorDynamicFit& accel,
                    const GraftOptions& opt) {
  return graftWhole(ref, basic, &gyro, &accel, opt);
}

Eigen::Vector2d referenceResidualFraction(const ImuProfile& reference, const ImuProfile& tested) {
  auto ratio = [](double a, double b) { return b > 0.0 ? a / b : 0.0; };
  return {ratio(reference.arw_rad_sqrt_s, tested.arw_rad_sqrt_s),
          ratio(reference.vrw_m_s_sqrt_s, tested.vrw_m_s_sqrt_s)};
}

}  // namespace graftnav
