// The candidate library's inputs that several terms share (vibration level, angular
// acceleration) and a term's contribution to the model.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "graftnav/imu/imu_error_terms.h"
#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/sample_noise.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

Eigen::VectorXd vibrationLevelPerBin(const ImuSeries& imu, const GridSpec& grid,
                                     const std::string& regressor_name, double window_s) {
  if (!VibrationRegressor::isKnownName(regressor_name))
    throw std::invalid_argument("vibrationLevelPerBin: unknown regressor '" + regressor_name + "'");
  const bool use_rate = VibrationRegressor::usesAngularRate(regressor_name);
  VibrationRegressor reg(window_s);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(grid.count);
  Eigen::VectorXi cnt = Eigen::VectorXi::Zero(grid.count);
  for (const ImuSample& s : imu) {
    if (!(s.dt_s > 0.0)) continue;
    const Eigen::Vector3d x = (use_rate ? s.dtheta_rad : s.dvel_m_s) / s.dt_s;
    const double r = reg.update(x, s.dt_s);
    const int i = static_cast<int>(std::floor((s.t_s - grid.t_begin_s) / grid.bin_s));
    if (i < 0 || i >= grid.count) continue;
    sum(i) += r;
    ++cnt(i);
  }
  // Bins without a sample (rate below the bin rate) take the previous bin's level.
  double last = 0.0;
  for (int i = 0; i < grid.count; ++i) {
    if (cnt(i) > 0) last = sum(i) / cnt(i);
    sum(i) = last;
  }
  return sum;
}

AngularAccelerationBins angularAccelerationPerBin(const ImuSeries& imu, const GridSpec& grid,
                                                  double max_noise_fraction) {
  if (imu.size() < 2)
    throw std::invalid_argument("angularAccelerationPerBin: fewer than 2 samples");
  // The bin mean of omega_dot over (a, b] is exactly (omega(b) - omega(a)) / (b - a), omega the
  // instantaneous rate: the tested IMU's velocity increments carry omega(t_k) x r at its sample
  // boundaries, so its bin means hold this exact mean. The rate at an edge t is estimated from
  // the reference's cumulative integral by Richardson extrapolation of two centred window means,
  // omega(t) ~ (4 m_w(t) - m_2w(t)) / 3 with m_w(t) the mean rate over (t - w/2, t + w/2]: a
  // window mean has gain sinc(f w) = 1 - (pi f w)^2 / 6 + O(f^4), and the combination cancels
  // the quadratic term. Its white-noise variance is (16 - 8 / 2 + 1 / 2) / 9 = 1.39 x one
  // window's, sigma^2 dt / w, and an edge difference over h doubles it; that noise in the
  // regressor biases r_m towards 0 by its share of the regressor's variance (errors in
  // variables), so the window is halved from h only while that share stays small.
  const CumulativeImu cum(imu);
  const double h = grid.bin_s;
  const double dt = medianSampleInterval(imu);
  const Eigen::Vector3d sigma =
      imu.size() >= 3 ? blockDifferenceNoiseSd(imu, SampleQuantity::angular_rate,
                                               samplesPerSecond(medianSampleInterval(imu)))
                      : Eigen::Vector3d::Zero();

  const auto regressor = [&](double w) {
    const auto windowMean = [&](double t, double width) -> Eigen::Vector3d {
      return ((cum.at(t + 0.5 * width) - cum.at(t - 0.5 * width)) / width).head<3>();
    };
    const auto rateAt = [&](double t) -> Eigen::Vector3d {
      return (4.0 * windowMean(t, w) - windowMean(t, 2.0 * w)) / 3.0;
    };
    Eigen::MatrixX3d out(grid.count, 3);
    Eigen::Vector3d prev = rateAt(grid.binStart(0));
    for (int i = 0; i < grid.count; ++i) {
      const Eigen::Vector3d cur = rateAt(grid.binStart(i + 1));
      out.row(i) = ((cur - prev) / h).transpose();
      prev = cur;
    }
    return out;
  };

  AngularAccelerationBins r;
  r.rate_noise_sd_rad_s = sigma;
  r.omega_dot_rad_s2 = regressor(h);
  r.window_s.setConstant(h);
  // A window shorter than a sample averages no further: the interpolated white noise keeps about
  // its per-sample variance, so the bound stops falling at w = dt.
  const auto noiseFraction = [&](const Eigen::MatrixX3d& z, double w, int a) {
    const double var = (z.col(a).array() - z.col(a).mean()).square().mean();
    const double noise = 2.0 * (25.0 / 18.0) * sigma(a) * sigma(a) * dt / (std::max(w, dt) * h * h);
    return var > 0.0 ? noise / var : 1.0;
  };
  for (int a = 0; a < 3; ++a) r.noise_fraction(a) = noiseFraction(r.omega_dot_rad_s2, h, a);
  // Down to a quarter sample: on a uniform record the cumulative integral is band limited between
  // samples (common_grid.h), so sub-sample windows follow vibration up to near Nyquist (gain
  // error 0.03 % at 40 Hz of a 100-Hz record for w = dt / 4, 15 % for w = 1.25 dt).
  for (double w = 0.5 * h; w >= 0.25 * dt * (1.0 - 1e-9); w *= 0.5) {
    const Eigen::MatrixX3d z = regressor(w);
    for (int a = 0; a < 3; ++a) {
      const double frac = noiseFraction(z, w, a);
      if (frac > max_noise_fraction) continue;
      r.omega_dot_rad_s2.col(a) = z.col(a);
      r.window_s(a) = w;
      r.noise_fraction(a) = frac;
    }
  }
  return r;
}

Eigen::VectorXd RegressorColumn::dense(int c) const {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(gridRows(c));
  if (actsOn(c)) v.segment(first_row, channel[c].size()) = channel[c];
  return v;
}

Eigen::MatrixXd termContribution(const CandidateTerm& term, const Eigen::VectorXd& theta, int n) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  for (std::size_t j = 0; j < term.columns.size(); ++j) {
    const double th = term.fixed() ? 1.0 : theta(static_cast<Eigen::Index>(j));
    const RegressorColumn& col = term.columns[j];
    for (int c = 0; c < kMismatchChannels; ++c)
      if (col.actsOn(c))
        out.col(c).segment(col.first_row, col.channel[c].size()) += th * col.channel[c];
  }
  return out;
}

}  // namespace graftnav
