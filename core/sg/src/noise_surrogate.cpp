#include "graftnav/sg/noise_surrogate.h"

#include <unsupported/Eigen/FFT>

#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <string>

namespace graftnav {

namespace {

// Bins 1 <= k < m/2 whose period m dt / k exceeds the model's slow period: a complex normal draw
// with the model's expected power, mirrored into bin m - k so that the series stays real.
void drawSlowBins(const SlowNoiseModel& model, int c, double dt_s, std::mt19937_64& rng,
                  std::vector<std::complex<double>>& spectrum) {
  const std::size_t m = spectrum.size();
  std::normal_distribution<double> n01(0.0, 1.0);
  for (std::size_t k = 1; 2 * k < m; ++k) {
    if (static_cast<double>(m) * dt_s / static_cast<double>(k) <= model.slow_period_s) break;
    const double omega = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(m);
    const double sd = std::sqrt(0.5 * model.binPower(c, omega, m, dt_s));
    spectrum[k] = {sd * n01(rng), sd * n01(rng)};
    spectrum[m - k] = std::conj(spectrum[k]);
  }
}

}  // namespace

std::size_t largestFiveSmooth(std::size_t limit) {
  for (std::size_t n = limit; n > 1; --n) {
    std::size_t m = n;
    for (std::size_t p : {2u, 3u, 5u}) {
      while (m % p == 0) m /= p;
    }
    if (m == 1) return n;
  }
  return 1;
}

double SlowNoiseModel::binPower(int c, double omega, std::size_t n, double dt_s) const {
  const double phi = std::exp(-dt_s / wander_tau_s[c]);
  const std::complex<double> d = 1.0 - phi * std::polar(1.0, -omega);
  const double white = white_density[c] * white_density[c] / dt_s;
  const double wander = wander_sigma[c] * wander_sigma[c] * (1.0 - phi * phi) / std::norm(d);
  return static_cast<double>(n) * (white + wander);
}

void SlowNoiseModel::validate() const {
  auto check = [](const Eigen::Matrix<double, 6, 1>& v, const char* name, bool positive) {
    for (int c = 0; c < 6; ++c) {
      if (!std::isfinite(v[c]) || v[c] < 0.0 || (positive && v[c] == 0.0)) {
        throw std::invalid_argument(std::string("SlowNoiseModel: ") + name + "[" +
                                    std::to_string(c) + "] = " + std::to_string(v[c]) +
                                    (positive ? " must be > 0" : " must be >= 0"));
      }
    }
  };
  check(white_density, "white_density", false);
  check(wander_sigma, "wander_sigma", false);
  check(wander_tau_s, "wander_tau_s", true);
  if (!(slow_period_s > 0.0)) {
    throw std::invalid_argument("SlowNoiseModel: slow_period_s = " + std::to_string(slow_period_s) +
                                " must be > 0");
  }
}

std::size_t surrogateLength(std::size_t n) { return largestFiveSmooth(2 * n); }

void phaseRandomizedSurrogateChannels(std::size_t n, const RecordRateFn& rate,
                                      const RecordLengthFn& dt_s, std::uint64_t seed,
                                      const SlowNoiseModel* slow,
                                      const SurrogateChannelFn& channel) {
  if (slow) slow->validate();
  if (n < 2)
    throw std::invalid_argument("phaseRandomizedSurrogate: the record needs >= 2 samples, got " +
                                std::to_string(n));
  const std::size_t m = surrogateLength(n);
  double span = 0.0;
  for (std::size_t j = 0; j < m; ++j) span += dt_s(surrogateSample(n, j));
  const double dt_mean = span / static_cast<double>(m);
  // One random phase per frequency, the same for all channels (keeps the cross-spectra), drawn
  // again from the seed for each channel. Bin 0 (the mean) and, for even m, the Nyquist bin stay
  // real and unchanged.
  auto rotate = [m, seed](std::vector<std::complex<double>>& spectrum) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI);
    for (std::size_t k = 1; 2 * k < m; ++k) {
      const std::complex<double> r = std::polar(1.0, u(rng));
      spectrum[k] *= r;
      spectrum[m - k] *= std::conj(r);
    }
  };
  Eigen::FFT<double> fft;
  std::mt19937_64 model_rng(seed ^ 0xA5A5A5A55A5A5A5Aull);
  std::vector<double> x(m);
  std::vector<std::complex<double>> spectrum, back;
  for (int c = 0; c < 6; ++c) {
    for (std::size_t j = 0; j < m; ++j) x[j] = rate(surrogateSample(n, j), c);
    fft.fwd(spectrum, x);
    rotate(spectrum);
    if (slow) drawSlowBins(*slow, c, dt_mean, model_rng, spectrum);
    fft.inv(back, spectrum);
    channel(c, back);
  }
}

LabErrorRates phaseRandomizedSurrogate(const LabErrorRates& record, std::uint64_t seed,
                                       const SlowNoiseModel* slow) {
  const std::size_t n = record.rate.size();
  if (n < 2 || record.dt_s.size() != n) {
    throw std::invalid_argument(
        "phaseRandomizedSurrogate: the record needs >= 2 samples with one dt_s each, got " +
        std::to_string(n) + " rates and " + std::to_string(record.dt_s.size()) + " dt_s");
  }
  const std::size_t m = surrogateLength(n);
  LabErrorRates out;
  out.rate.assign(m, Eigen::Matrix<double, 6, 1>::Zero());
  out.dt_s.resize(m);
  for (std::size_t j = 0; j < m; ++j) out.dt_s[j] = record.dt_s[surrogateSample(n, j)];
  phaseRandomizedSurrogateChannels(
      n, [&record](std::size_t j, int c) { return record.rate[j][c]; },
      [&record](std::size_t j) { return record.dt_s[j]; }, seed, slow,
      [&out](int c, const std::vector<std::complex<double>>& back) {
        for (std::size_t j = 0; j < back.size(); ++j) out.rate[j][c] = back[j].real();
      });
  return out;
}

}  // namespace graftnav
