#pragma once
// First-order Gauss-Markov process, discretized exactly for any sample interval, and the seeded
// standard-normal source every stochastic IMU error term draws from.
//
// Continuous model (per axis): dx/dt = -x / tau + w(t), stationary standard deviation sigma.
// Exact discretization over an interval dt (any dt > 0, the intervals may vary):
//   x_{k+1} = phi x_k + w_k,  phi = exp(-dt / tau),  var(w_k) = sigma^2 (1 - exp(-2 dt / tau)),
// so var(x_k) stays sigma^2 and corr(x_k, x_{k+m}) = exp(-m dt / tau) at every rate.
// tau = +infinity is allowed and gives a random constant (phi = 1, w = 0).
//
// Randomness: std::mt19937_64 (fully specified by the C++ standard) feeding our own Box-Muller
// transform, because std::normal_distribution is implementation-defined; a seed therefore gives
// the same numbers with every compiler and standard library.

#include <Eigen/Core>
#include <cstdint>
#include <random>

namespace graftnav {

// Seeded N(0, 1) source: mt19937_64 + Box-Muller (both outputs used).
class StandardNormalSampler {
 public:
  explicit StandardNormalSampler(uint64_t seed = 0) { reseed(seed); }
  void reseed(uint64_t seed);
  double next();
  Eigen::Vector3d next3() {
    const double a = next();
    const double b = next();
    const double c = next();
    return Eigen::Vector3d(a, b, c);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Derives the seed of an independent random stream from a user seed and a stream id
// (SplitMix64 of seed and id), so that each error term has its own stream and switching one term
// on or off does not change the realization of the others.
uint64_t deriveStreamSeed(uint64_t seed, uint64_t stream_id);

// Parameters of a 3-axis first-order Gauss-Markov process (one correlation time for all axes).
struct GaussMarkovParams {
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();  // stationary 1-sigma per axis (SI)
  double tau_s = 3600.0;                            // correlation time (s), > 0, may be +inf
  // true: x_0 ~ N(0, sigma^2) (the process has been running, stationary from the first sample);
  // false: x_0 = 0.
  bool start_stationary = true;
  bool isActive() const { return (sigma.array() != 0.0).any(); }
};

class GaussMarkov {
 public:
  explicit GaussMarkov(const GaussMarkovParams& params = GaussMarkovParams());

  // phi = exp(-dt / tau); 1 for tau = inf.
  static double transition(double dt_s, double tau_s);
  // Standard deviation of the driving noise over dt: sigma sqrt(1 - exp(-2 dt / tau)), computed
  // with expm1 so that it stays accurate for dt << tau.
  static double drivingNoiseStd(double sigma, double dt_s, double tau_s);

  // Sets x_0 according to params.start_stationary (draws from rng when stationary).
  void initialize(StandardNormalSampler& rng);
  void setState(const Eigen::Vector3d& x) { x_ = x; }
  // x <- phi x + w over an interval dt_s (> 0); returns the new state.
  const Eigen::Vector3d& propagate(double dt_s, StandardNormalSampler& rng);

  const Eigen::Vector3d& state() const { return x_; }
  const GaussMarkovParams& params() const { return params_; }

 private:
  GaussMarkovParams params_;
  Eigen::Vector3d x_ = Eigen::Vector3d::Zero();
};

}  // namespace graftnav
