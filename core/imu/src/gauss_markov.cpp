#include "graftnav/imu/gauss_markov.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {

void StandardNormalSampler::reseed(uint64_t seed) {
  engine_.seed(seed);
  has_spare_ = false;
  spare_ = 0.0;
}

double StandardNormalSampler::next() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Two uniforms from the top 53 bits: u1 in (0, 1] (log finite), u2 in [0, 1).
  constexpr double kTwoPow53Inv = 1.0 / 9007199254740992.0;
  const double u1 = (static_cast<double>(engine_() >> 11) + 1.0) * kTwoPow53Inv;
  const double u2 = static_cast<double>(engine_() >> 11) * kTwoPow53Inv;
  constexpr double kTwoPi = 6.283185307179586477;
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(kTwoPi * u2);
  has_spare_ = true;
  return r * std::cos(kTwoPi * u2);
}

uint64_t deriveStreamSeed(uint64_t seed, uint64_t stream_id) {
  // SplitMix64 finalizer applied to the seed advanced by the stream id.
  uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream_id + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

GaussMarkov::GaussMarkov(const GaussMarkovParams& params) : params_(params) {
  if (!(params_.tau_s > 0.0)) {
    throw std::invalid_argument("GaussMarkov: tau_s = " + std::to_string(params_.tau_s) +
                                " must be > 0");
  }
  if (!params_.sigma.allFinite() || (params_.sigma.array() < 0.0).any()) {
    throw std::invalid_argument("GaussMarkov: sigma must be finite and >= 0");
  }
}

double GaussMarkov::transition(double dt_s, double tau_s) {
  if (std::isinf(tau_s)) return 1.0;
  return std::exp(-dt_s / tau_s);
}

double GaussMarkov::drivingNoiseStd(double sigma, double dt_s, double tau_s) {
  if (std::isinf(tau_s)) return 0.0;
  return sigma * std::sqrt(-std::expm1(-2.0 * dt_s / tau_s));
}

void GaussMarkov::initialize(StandardNormalSampler& rng) {
  if (params_.start_stationary) {
    x_ = params_.sigma.cwiseProduct(rng.next3());
  } else {
    x_.setZero();
  }
}

const Eigen::Vector3d& GaussMarkov::propagate(double dt_s, StandardNormalSampler& rng) {
  if (!(dt_s > 0.0)) {
    throw std::invalid_argument("GaussMarkov::propagate: dt_s = " + std::to_string(dt_s) +
                                " must be > 0");
  }
  const double phi = transition(dt_s, params_.tau_s);
  const Eigen::Vector3d w =
      params_.sigma * (GaussMarkov::drivingNoiseStd(1.0, dt_s, params_.tau_s));
  x_ = phi * x_ + w.cwiseProduct(rng.next3());
  return x_;
}

}  // namespace graftnav
