#include "graftnav/sg/realization.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace graftnav {
namespace {

using Vec6 = PowerOnErrors::Vec6;

// One independent stream per realization and purpose (splitmix64 of seed, k, purpose).
std::uint64_t streamSeed(std::uint64_t seed, int k, int purpose) {
  std::uint64_t z =
      seed + 0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(k) * 8u + purpose + 1u);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double repeatability(double given, double instability) {
  return given >= 0.0 ? given : instability;
}

// The record holds K disjoint segments of the field span (each one lab sample longer).
bool disjointSegmentsFit(const BasicErrorSignal& basic, int K, double span_s) {
  const double T = basic.recordLength_s();
  const double dt = T / static_cast<double>(basic.sampleCount());  // mean lab sample length
  return T >= K * (span_s + dt);
}

double startOffset(const RealizationOptions& o, const BasicErrorSignal& basic, double span_s, int k,
                   std::mt19937_64& rng) {
  if (!o.vary_segment) return 0.0;
  const double T = basic.recordLength_s();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int K = o.count;
  const double dt = T / static_cast<double>(basic.sampleCount());  // mean lab sample length
  if (disjointSegmentsFit(basic, K, span_s)) {
    // Disjoint segments: segment k starts in stratum k (one sample in, so that moving back to a
    // sample boundary stays inside it) early enough to end inside it.
    const double stratum = T / K;
    return basic.sampleBoundaryAtOrBefore(k * stratum + dt + u(rng) * (stratum - span_s - dt));
  }
  const double stratum = 2.0 * T / K;
  return basic.sampleBoundaryAtOrBefore(k * stratum + u(rng) * stratum);
}

// Gauss-Markov path sampled every `step_s` from zero: x_{j+1} = phi x_j + sigma sqrt(1 - phi^2) w.
std::vector<Vec6> wanderKnots(const ImuProfile& p, double step_s, double span_s,
                              std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const int n = static_cast<int>(std::ceil(span_s / step_s - 1e-9)) + 1;  // knots cover the span
  const double phi_g = std::exp(-step_s / p.gyro_bias_corr_time_s);
  const double phi_a = std::exp(-step_s / p.accel_bias_corr_time_s);
  const double q_g = p.gyro_bias_instability_rad_s * std::sqrt(1.0 - phi_g * phi_g);
  const double q_a = p.accel_bias_instability_m_s2 * std::sqrt(1.0 - phi_a * phi_a);
  std::vector<Vec6> knots(n, Vec6::Zero());
  for (int j = 1; j < n; ++j) {
    for (int i = 0; i < 3; ++i) {
      knots[j][i] = phi_g * knots[j - 1][i] + q_g * n01(rng);
      knots[j][3 + i] = phi_a * knots[j - 1][3 + i] + q_a * n01(rng);
    }
  }
  return knots;
}

// The tested IMU's stated noise (profile) as the model of the surrogate's slow content.
SlowNoiseModel slowNoiseModel(const ImuProfile& p, double slow_period_s) {
  SlowNoiseModel m;
  m.white_density << Eigen::Vector3d::Constant(p.arw_rad_sqrt_s),
      Eigen::Vector3d::Constant(p.vrw_m_s_sqrt_s);
  m.wander_sigma << Eigen::Vector3d::Constant(p.gyro_bias_instability_rad_s),
      Eigen::Vector3d::Constant(p.accel_bias_instability_m_s2);
  m.wander_tau_s << Eigen::Vector3d::Constant(p.gyro_bias_corr_time_s),
      Eigen::Vector3d::Constant(p.accel_bias_corr_time_s);
  m.slow_period_s = slow_period_s;
  return m;
}

}  // namespace

void RealizationOptions::validate() const {
  if (count < 1)
    throw std::invalid_argument("realizations: count must be >= 1, got " + std::to_string(count));
  if (!(slow_period_s >= 0.0)) {
    throw std::invalid_argument("realizations: slow_period_s must be >= 0, got " +
                                std::to_string(slow_period_s));
  }
  if (lab_sessions < 1) {
    throw std::invalid_argument("realizations: lab_sessions must be >= 1, got " +
                                std::to_string(lab_sessions));
  }
}

std::vector<RealizationDraw> drawRealizations(const RealizationOptions& o,
                                              const BasicErrorSignal& basic, const ImuProfile& p,
                                              double span_s) {
  o.validate();
  if (!(span_s > 0.0)) throw std::invalid_argument("drawRealizations: field span must be > 0 s");
  const double sd_factor = std::sqrt(1.0 + 1.0 / o.lab_sessions);
  const double rep_g =
      repeatability(p.gyro_bias_repeatability_rad_s, p.gyro_bias_instability_rad_s) * sd_factor;
  const double rep_a =
      repeatability(p.accel_bias_repeatability_m_s2, p.accel_bias_instability_m_s2) * sd_factor;
  const double T = basic.recordLength_s();
  // One realization is the seed's single graft: the lab record as it is, no power-on draws.
  const bool power_on = o.count > 1;
  // A record shorter than the field test: its slow content is one draw that every realization
  // would share (offsets 2T/K apart see nearly the same wander at the outages). A record at least
  // as long as the field test supplies realizations whose offsets are at least 2 spans / K apart,
  // which on a 1-hour record is minutes, longer than the wander's correlation times.
  const bool surrogate = o.vary_segment && o.surrogate_short_record && T < span_s;
  std::vector<RealizationDraw> draws(o.count);
  for (int k = 0; k < o.count; ++k) {
    RealizationDraw& d = draws[k];
    d.index = k;
    std::mt19937_64 seg_rng(streamSeed(o.seed, k, 0)), bias_rng(streamSeed(o.seed, k, 1)),
        wander_rng(streamSeed(o.seed, k, 2));
    d.start_offset_s = startOffset(o, basic, span_s, k, seg_rng);
    if (power_on && surrogate) {
      d.surrogate_seed = streamSeed(o.seed, k, 3);
      if (o.slow_period_s > 0.0) d.slow_noise = slowNoiseModel(p, o.slow_period_s);
    }
    if (power_on && o.vary_turn_on_bias) {
      std::normal_distribution<double> n01(0.0, 1.0);
      for (int i = 0; i < 3; ++i) d.power_on.gyro_bias_rad_s[i] = rep_g * n01(bias_rng);
      for (int i = 0; i < 3; ++i) d.power_on.accel_bias_m_s2[i] = rep_a * n01(bias_rng);
    }
    // The record (or a surrogate with modelled slow content, which spans the mirror period 2T)
    // holds the wander up to its length; the knots add only what is slower.
    const double held_s = d.slow_noise ? 2.0 * T : T;
    if (power_on && o.vary_bias_wander && span_s > held_s) {
      d.power_on.wander_step_s = held_s;
      d.power_on.wander_knots = wanderKnots(p, held_s, span_s, wander_rng);
    }
  }
  return draws;
}

GraftOptions graftOptionsFor(const RealizationDraw& draw) {
  GraftOptions g;
  g.start_offset_s = draw.start_offset_s;
  g.power_on = draw.power_on;
  g.surrogate_seed = draw.surrogate_seed;
  g.surrogate_slow_noise = draw.slow_noise;
  return g;
}

double sharedSampleFraction(const std::vector<RealizationDraw>& draws,
                            const BasicErrorSignal& basic) {
  const double period = 2.0 * basic.recordLength_s();
  const double tol = 0.5 * basic.recordLength_s() / static_cast<double>(basic.sampleCount());
  int pairs = 0, shared = 0;
  for (std::size_t a = 0; a < draws.size(); ++a) {
    for (std::size_t b = a + 1; b < draws.size(); ++b) {
      ++pairs;
      if (draws[a].surrogate_seed || draws[b].surrogate_seed) continue;
      const double d =
          std::fmod(std::fabs(draws[a].start_offset_s - draws[b].start_offset_s), period);
      if (std::min(d, period - d) < tol) ++shared;
    }
  }
  return pairs == 0 ? 0.0 : static_cast<double>(shared) / pairs;
}

}  // namespace graftnav
