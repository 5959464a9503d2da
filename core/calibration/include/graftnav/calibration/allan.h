#pragma once
// Overlapping Allan variance on rate samples, with confidence intervals, and a weighted
// least-squares fit of the standard noise-term model (IEEE Std 952 terms):
//   AVAR(tau) = 3 Q^2 / tau^2 (optional) + N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3
// N: white noise (ARW rad/sqrt(s) / VRW m/s/sqrt(s)), read at tau = 1 s on the slope -1/2 line;
// B: bias instability (flat part; the minimum of ADEV / 0.664);
// K: rate random walk (slope +1/2 line, read at tau = 3 s).
//
// Overlapping estimator with cluster size m (tau = m dt), from the cumulative angle theta_k:
//   AVAR(tau) = sum_{k=0}^{N-2m} (theta_{k+2m} - 2 theta_{k+m} + theta_k)^2 / (2 tau^2 (N - 2m + 1))
// Confidence: relative 1-sigma error of ADEV ~ 1 / sqrt(2 (N/m - 1)) (IEEE Std 952 App. C).
//
// The fit is done on ADEV with residual (sqrt(model(tau)) - adev(tau)) / (w(tau) adev(tau)),
// w = sqrt(rel^2 + floor^2) (see AllanFitOptions), over
// the cluster times, with the variance coefficients c = [N^2, B^2, K^2 (, Q^2)] >= 0 as Ceres
// parameters; the covariance of c (ceres::Covariance, scaled by max(1, reduced chi-square)) is
// propagated to N, B, K by sigma_N = sigma_{N^2} / (2 N). Because the overlapping estimates at
// nearby tau are correlated, octave spacing (default) keeps the weights honest.

#include <Eigen/Core>
#include <vector>

#include "graftnav/calibration/calibration_result.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct AllanOptions {
  bool octave = true;                 // m = 1, 2, 4, ...; false: dense log spacing
  int points_per_decade = 10;         // for dense spacing
  double max_cluster_fraction = 0.1;  // largest m <= fraction * N (rel. error <= ~0.24 at 0.1)
  void validate() const;
};

struct AllanCurve {
  double dt_s = 0.0;
  std::size_t n = 0;
  std::vector<double> tau_s;
  std::vector<long> m;
  std::vector<Eigen::Vector3d> adev;  // per axis
  std::vector<double> rel_error;      // 1 / sqrt(2 (N/m - 1))
};

// rate samples (one Vector3d a sample, rad/s or m/s^2) at a constant interval dt_s.
// Throws std::invalid_argument for fewer than 16 samples or dt <= 0.
AllanCurve allanDeviation(const std::vector<Eigen::Vector3d>& rate, double dt_s,
                          const AllanOptions& options = {});
// From an ImuSeries (gyro: dtheta/dt, else dvel/dt); dt is the mean interval.
AllanCurve allanDeviation(const ImuSeries& imu, bool gyro, const AllanOptions& options = {});

struct AllanFitOptions {
  bool fit_quantization = false;
  double min_tau_s = 0.0;  // restrict the fit range (0 = all)
  double max_tau_s = 0.0;  // 0 = all
  // Cluster times shorter than this many samples are left out: real sensors low-pass filter
  // their output, which bends the shortest-tau part of the curve away from the noise model.
  int min_cluster_samples = 8;
  // Model-error floor added in quadrature to the relative confidence of each ADEV point (the
  // short-tau points have tiny statistical errors, while the five-term model is only an
  // approximation of a real spectrum).
  double relative_error_floor = 0.01;
  void validate() const;
};

struct AllanFit {
  AllanTerms terms;
  Eigen::Vector3d quantization = Eigen::Vector3d::Zero();
  Eigen::Vector3d reduced_chi2 = Eigen::Vector3d::Zero();
  // Read-off values for comparison: ADEV(1 s) on the fitted curve's -1/2 slope line (= N),
  // min ADEV / 0.664 of the measured curve, and the tau of that minimum.
  Eigen::Vector3d readoff_bias_instability = Eigen::Vector3d::Zero();
  Eigen::Vector3d tau_min_s = Eigen::Vector3d::Zero();
  // Model ADEV at tau (for plots).
  double modelAdev(int axis, double tau_s) const;
};

AllanFit fitAllanNoiseTerms(const AllanCurve& curve, const AllanFitOptions& options = {});

}  // namespace graftnav
