#include "graftnav/sg/grafting.h"

#include <algorithm>
#include <cmath>
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
  tau_end_s_.reserve(e.size());
  cum_.reserve(e.size());
  rate_.reserve(e.size());
  double tau = 0.0;
  Vec6 c = Vec6::Zero();
  for (const ImuSample& s : e) {
    if (!(s.dt_s > 0.0)) {
      throw std::invalid_argument("BasicErrorSignal: sample at t=" + std::to_string(s.t_s) +
                                  " has non-positive dt " + std::to_string(s.dt_s));
    }
    Vec6 inc;
    inc << s.dtheta_rad, s.dvel_m_s;
    tau += s.dt_s;
    c += inc;
    tau_end_s_.push_back(tau);
    cum_.push_back(c);
    rate_.push_back(inc / s.dt_s);
  }
  record_length_s_ = tau;
}

Eigen::Vector3d BasicErrorSignal::meanGyro_rad_s() const {
  return cum_.back().head<3>() / record_length_s_;
}
Eigen::Vector3d BasicErrorSignal::meanAccel_m_s2() const {
  return cum_.back().tail<3>() / record_length_s_;
}

Vec6 BasicErrorSignal::withinRecord(double tau) const {
  if (tau <= 0.0) return Vec6::Zero();
  if (tau >= record_length_s_) return cum_.back();
  // First sample whose end is >= tau; the rate is constant inside it.
  const auto it = std::lower_bound(tau_end_s_.begin(), tau_end_s_.end(), tau);
  const std::size_t j = static_cast<std::size_t>(it - tau_end_s_.begin());
  const double over = tau_end_s_[j] - tau;  // part of sample j after tau
  return cum_[j] - rate_[j] * over;
}

Vec6 BasicErrorSignal::cumulative(double u) const {
  if (u <= 0.0) return Vec6::Zero();
  const double T = record_length_s_;
  const double m = std::floor(u / T);
  const double tau = u - m * T;
  const long tile = static_cast<long>(m);
  const Vec6 whole = cum_.back();
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
    const auto it = std::upper_bound(tau_end_s_.begin(), tau_end_s_.end(), tau);
    const double b = it == tau_end_s_.begin() ? 0.0 : *(it - 1);
    return m * T + b;
  }
  // Mirrored tile: boundaries at T - tau_end_j; the largest one <= tau is T minus the smallest
  // tau_end_j >= T - tau.
  const auto it = std::lower_bound(tau_end_s_.begin(), tau_end_s_.end(), T - tau);
  const double b = it == tau_end_s_.end() ? 0.0 : T - *it;
  return m * T + std::max(0.0, b);
}

LabErrorRates BasicErrorSignal::rates() const {
  LabErrorRates r;
  r.rate = rate_;
  r.dt_s.resize(tau_end_s_.size());
  for (std::size_t j = 0; j < tau_end_s_.size(); ++j) r.dt_s[j] = tau_end_s_[j] - sampleStart_s(j);
  return r;
}

BasicErrorSignal BasicErrorSignal::phaseRandomized(std::uint64_t seed,
                                                   const SlowNoiseModel* slow) const {
  const LabErrorRates s = phaseRandomizedSurrogate(rates(), seed, slow);
  ImuSeries inc(s.rate.size());
  double t = 0.0;
  for (std::size_t j = 0; j < inc.size(); ++j) {
    t += s.dt_s[j];
    inc[j].t_s = t;
    inc[j].dt_s = s.dt_s[j];
    inc[j].dtheta_rad = s.rate[j].head<3>() * s.dt_s[j];
    inc[j].dvel_m_s = s.rate[j].tail<3>() * s.dt_s[j];
  }
  return BasicErrorSignal(inc);
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
    surrogate_.emplace(record.phaseRandomized(
        *opt.surrogate_seed, opt.surrogate_slow_noise ? &*opt.surrogate_slow_noise : nullptr));
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
