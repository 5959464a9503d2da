#pragma once
// A phase-randomized surrogate of a lab error record: a new series with the record's mean, power
// spectrum and cross-spectra between its six channels (so its Allan deviation up to the record
// length), but random Fourier phases, so two surrogates drawn with different seeds are
// independent realizations of the same stationary Gaussian process (Theiler et al. 1992, "Testing
// for nonlinearity in time series: the method of surrogate data").
//
// Grafted realizations use it when the static record is too short to give each realization its
// own segment (sg/realization.h): segments of a short record reuse the same few minutes of noise
// in another order, so the navigation errors of the realizations are far more alike than those of
// two power-ons of the IMU, and the predictive interval comes out too narrow.
//
// The surrogate is built on the mirrored record (record, then the record reversed), which is
// periodic and continuous, so the discrete Fourier transform sees no jump at the ends. Its length
// is the largest number of the form 2^a 3^b 5^c not above twice the record's sample count (a fast
// transform whatever the count; at most about 2 % of the mirrored record is left out). The
// surrogate is Gaussian: non-Gaussian features of the real lab noise (quantization steps, spikes)
// are not reproduced.

#include <Eigen/Core>
#include <complex>
#include <cstdint>
#include <functional>
#include <vector>

namespace graftnav {

struct LabErrorRates {
  std::vector<Eigen::Matrix<double, 6, 1>> rate;  // [gyro rad/s; accel m/s^2] per lab sample
  std::vector<double> dt_s;                       // length of each lab sample
};

// The stated noise of the tested IMU per channel [gyro x, y, z, accel x, y, z]: white-noise density
// (rate unit sqrt(s): rad/sqrt(s), m/s/sqrt(s)) and a first-order Gauss-Markov bias wander
// (sigma in rate units, correlation time). Fourier bins whose period is longer than
// `slow_period_s` take a fresh draw of this model instead of the record's own amplitude.
//
// Why: a record of length T holds only about T / P cycles of content of period P, so its
// periodogram there is a draw with a few degrees of freedom (one bin: +-100 % in power). All
// realizations grafted from one record share that draw while the field has its own; on the
// 15-minute MEMS cases, where the in-outage bias wander (periods of minutes) sets the vertical and
// attitude errors, the intervals then covered REAL in only 70-80 % of seeds.
struct SlowNoiseModel {
  Eigen::Matrix<double, 6, 1> white_density = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> wander_sigma = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> wander_tau_s = Eigen::Matrix<double, 6, 1>::Constant(3600.0);
  double slow_period_s = 20.0;
  // Expected |DFT bin|^2 of channel c at angular frequency omega (rad per sample) for n samples of
  // dt_s: n (density^2 / dt + sigma^2 (1 - phi^2) / |1 - phi e^{-i omega}|^2), phi = e^{-dt/tau}.
  double binPower(int c, double omega, std::size_t n, double dt_s) const;
  // Throws std::invalid_argument naming the field when a value is negative or not finite.
  void validate() const;
};

// Largest n <= limit with no prime factor above 5 (limit >= 1).
std::size_t largestFiveSmooth(std::size_t limit);

// The surrogate of `record` for `seed`: same mean, same periodogram of the mirrored record per
// channel and between channels (one random phase per frequency, shared by the six channels).
// Throws std::invalid_argument when the record has fewer than 2 samples or rate and dt_s differ
// in length.
// With `slow`, bins of period longer than slow->slow_period_s are drawn from the model (complex
// normal with the model's expected power) instead of keeping the record's amplitude.
LabErrorRates phaseRandomizedSurrogate(const LabErrorRates& record, std::uint64_t seed,
                                       const SlowNoiseModel* slow = nullptr);

// The same surrogate without copies of the record or of the result: n lab samples whose rate of
// channel c at sample j is rate(j, c) and whose length is dt_s(j); channel(c, values) receives
// the surrogate's surrogateLength(n) rates of channel c (values[j].real()), one channel after
// the other. The lengths of the surrogate's samples are dt_s of the mirrored record
// (surrogateSample). Throws std::invalid_argument when n < 2.
using RecordRateFn = std::function<double(std::size_t j, int c)>;
using RecordLengthFn = std::function<double(std::size_t j)>;
using SurrogateChannelFn =
    std::function<void(int c, const std::vector<std::complex<double>>& values)>;
void phaseRandomizedSurrogateChannels(std::size_t n, const RecordRateFn& rate,
                                      const RecordLengthFn& dt_s, std::uint64_t seed,
                                      const SlowNoiseModel* slow,
                                      const SurrogateChannelFn& channel);
// How many samples the surrogate of n samples has (the mirrored record cut to a fast transform
// length), and which record sample its sample j repeats.
std::size_t surrogateLength(std::size_t n);
inline std::size_t surrogateSample(std::size_t n, std::size_t j) {
  return j < n ? j : 2 * n - 1 - j;
}

}  // namespace graftnav
