#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "graftnav/eval/evaluation.h"
#include "graftnav/mismatch/locate.h"

namespace graftnav {
namespace {

Eigen::VectorXd movingAverage(const Eigen::VectorXd& x, int half) {
  const int n = static_cast<int>(x.size());
  Eigen::VectorXd cs(n + 1);
  cs(0) = 0.0;
  for (int i = 0; i < n; ++i) cs(i + 1) = cs(i) + x(i);
  Eigen::VectorXd out(n);
  for (int i = 0; i < n; ++i) {
    const int a = std::max(0, i - half), b = std::min(n, i + half + 1);
    out(i) = (cs(b) - cs(a)) / (b - a);
  }
  return out;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(pos));
  const std::size_t j = std::min(v.size() - 1, i + 1);
  return v[i] + (pos - i) * (v[j] - v[i]);
}

struct WindowStats {
  int bins = 0, windows = 0;
  double n_eff = 1.0;
  std::vector<double> ms;  // per window
};

WindowStats windowStats(const Eigen::VectorXd& r, const GridSpec& grid, double window_s) {
  WindowStats w;
  const int n = static_cast<int>(r.size());
  w.bins = std::max(2, static_cast<int>(std::round(window_s / grid.bin_s)));
  w.windows = std::max(1, n / w.bins);
  const Eigen::VectorXd z = r.array() - r.mean();
  const double den = z.squaredNorm();
  double rho = den > 0.0 ? z.head(n - 1).dot(z.tail(n - 1)) / den : 0.0;
  // The lag-1 correlation of the noise, from the first differences, is not inflated by slow
  // deterministic structure the way the raw correlation is: var(dz) = 2 var(z) (1 - rho).
  const Eigen::VectorXd dz = z.tail(n - 1) - z.head(n - 1);
  double rho_d = 1.0 - dz.squaredNorm() / (n - 1) / (2.0 * den / n);
  rho = std::clamp(std::min(rho, rho_d), 0.0, 0.95);
  w.n_eff = std::max(2.0, w.bins * (1.0 - rho) / (1.0 + rho));
  w.ms.resize(w.windows);
  for (int k = 0; k < w.windows; ++k) {
    const int a = k * w.bins;
    const int b = (k == w.windows - 1) ? n : a + w.bins;
    w.ms[k] = z.segment(a, b - a).squaredNorm() / (b - a);
  }
  return w;
}

}  // namespace

const std::vector<std::string>& mismatchChannelNames() {
  static const std::vector<std::string> names = {"gyro_x",  "gyro_y",  "gyro_z",
                                                 "accel_x", "accel_y", "accel_z"};
  return names;
}

std::vector<std::string> labelRegimes(const BinnedImu& x, const Eigen::VectorXd& temperature,
                                      const RegimeOptions& o) {
  const int n = x.size();
  const int half = std::max(0, static_cast<int>(std::round(0.5 * o.smooth_s / x.grid.bin_s)));
  const Eigen::VectorXd wz = movingAverage(x.omega_rad_s.col(2), half);
  Eigen::VectorXd wn(n);
  for (int i = 0; i < n; ++i) wn(i) = x.omega_rad_s.row(i).norm();
  wn = movingAverage(wn, half);
  // Forward acceleration: forward specific force minus its slow trend (the gravity component of a
  // slowly changing pitch), trend = moving average over trend_s.
  const int trend_half = std::max(1, static_cast<int>(std::round(0.5 * o.trend_s / x.grid.bin_s)));
  const Eigen::VectorXd fx = x.f_m_s2.col(0);
  const Eigen::VectorXd ax = movingAverage(fx - movingAverage(fx, trend_half), half);
  const Eigen::VectorXd vib = movingAverage(x.f_within_rms_m_s2, half);
  std::vector<double> vv(vib.data(), vib.data() + n);
  const double vib_floor = quantile(vv, 0.1), vib_med = quantile(vv, 0.5);
  Eigen::VectorXd dT = Eigen::VectorXd::Zero(n);
  const bool has_temp = temperature.size() == n && temperature.allFinite();
  if (has_temp) {
    const int h = std::max(1, static_cast<int>(std::round(15.0 / x.grid.bin_s)));
    for (int i = 0; i < n; ++i) {
      const int a = std::max(0, i - h), b = std::min(n - 1, i + h);
      dT(i) = b > a ? (temperature(b) - temperature(a)) / ((b - a) * x.grid.bin_s) : 0.0;
    }
  }
  std::vector<std::string> out(n);
  for (int i = 0; i < n; ++i) {
    if (wn(i) < o.stopped_rate_rad_s && std::abs(ax(i)) < o.stopped_accel_m_s2 &&
        vib(i) <= 2.0 * vib_floor + 1e-3)
      out[i] = "stopped";
    else if (wz(i) > o.turn_rate_rad_s)
      out[i] = "turning_right";
    else if (wz(i) < -o.turn_rate_rad_s)
      out[i] = "turning_left";
    else if (ax(i) > o.accel_m_s2)
      out[i] = "accelerating";
    else if (ax(i) < -o.accel_m_s2)
      out[i] = "braking";
    else if (has_temp && std::abs(dT(i)) > o.temperature_ramp_degC_s)
      out[i] = "temperature_ramp";
    else if (vib(i) > o.vibration_factor * vib_med && vib(i) > o.vibration_min_m_s2)
      out[i] = "high_vibration";
    else
      out[i] = "cruising";
  }
  return out;
}

Eigen::Matrix<double, 6, 1> windowNoiseLevel(const Eigen::MatrixXd& residual, const GridSpec& grid,
                                             const LocateOptions& options) {
  Eigen::Matrix<double, 6, 1> out;
  for (int c = 0; c < 6; ++c) {
    const WindowStats w = windowStats(residual.col(c), grid, options.window_s);
    const double q = quantile(w.ms, options.noise_quantile);
    // The q-quantile of (noise ms) x chi2(n_eff)/n_eff.
    const double scale = chiSquareQuantile(options.noise_quantile, w.n_eff) / w.n_eff;
    out(c) = q / std::max(scale, 1e-3);
  }
  return out;
}

std::vector<LocatedSpan> locateResidual(const Eigen::MatrixXd& residual, const GridSpec& grid,
                                        const std::vector<std::string>& regimes,
                                        const LocateOptions& options,
                                        const Eigen::Matrix<double, 6, 1>* noise_ms) {
  if (residual.cols() != 6 || residual.rows() != grid.count ||
      static_cast<int>(regimes.size()) != grid.count)
    throw std::invalid_argument("locateResidual: residual, grid and regimes differ in size");
  const Eigen::Matrix<double, 6, 1> noise =
      noise_ms ? *noise_ms : windowNoiseLevel(residual, grid, options);
  std::vector<LocatedSpan> spans;
  for (int c = 0; c < 6; ++c) {
    const WindowStats w = windowStats(residual.col(c), grid, options.window_s);
    const double limit = noise(c) * chiSquareQuantile(1.0 - options.false_alarm, w.n_eff) / w.n_eff;
    // A non-finite residual (an input value out of range upstream) makes every comparison false: the
    // span search below would never advance. Refuse it, naming the channel.
    const bool finite_ms =
        std::all_of(w.ms.begin(), w.ms.end(), [](double v) { return std::isfinite(v); });
    if (!std::isfinite(limit) || !finite_ms)
      throw std::invalid_argument(
          std::string("locateResidual: channel ") + mismatchChannelNames()[c] +
          ": the residual's window mean squares or their noise limit are not finite (limit " +
          std::to_string(limit) + "); check the IMU inputs for out-of-range values");
    int k = 0;
    while (k < w.windows) {
      if (!(w.ms[k] > limit)) {
        ++k;
        continue;
      }
      int e = k;
      double sum_ms = 0.0;
      while (e < w.windows && w.ms[e] > limit) sum_ms += w.ms[e++];
      const int a = k * w.bins;
      const int b = (e == w.windows) ? grid.count : e * w.bins;
      std::map<std::string, int> votes;
      for (int i = a; i < b; ++i) ++votes[regimes[i]];
      LocatedSpan s;
      s.channel = c;
      s.t_start = grid.binStart(a);
      s.t_end = grid.binStart(b);
      s.regime = std::max_element(votes.begin(), votes.end(), [](const auto& p, const auto& q) {
                   return p.second < q.second;
                 })->first;
      s.excess_rms = std::sqrt(std::max(0.0, sum_ms / (e - k) - noise(c)));
      spans.push_back(s);
      k = e;
    }
  }
  // Keep the largest excesses relative to each channel's noise.
  std::sort(spans.begin(), spans.end(),
            [&](const LocatedSpan& a, const LocatedSpan& b) { return a.t_start < b.t_start; });
  if (static_cast<int>(spans.size()) > options.max_entries) {
    std::vector<std::pair<double, std::size_t>> score;
    for (std::size_t i = 0; i < spans.size(); ++i) {
      const int c = spans[i].channel;
      score.push_back({spans[i].excess_rms / std::sqrt(std::max(noise(c), 1e-300)), i});
    }
    std::sort(score.rbegin(), score.rend());
    std::vector<LocatedSpan> kept;
    for (int i = 0; i < options.max_entries; ++i) kept.push_back(spans[score[i].second]);
    std::sort(kept.begin(), kept.end(),
              [](const LocatedSpan& a, const LocatedSpan& b) { return a.t_start < b.t_start; });
    spans = kept;
  }
  return spans;
}

}  // namespace graftnav
