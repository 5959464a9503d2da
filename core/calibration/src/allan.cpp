#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/calibration/allan.h"

namespace graftnav {
namespace {

constexpr double kFlickerFactor = 0.66432;  // sqrt(2 ln2 / pi)
constexpr double kFlickerVar = 0.44130;     // 2 ln2 / pi

// Whitened ADEV residual for one tau. Parameters c = [N^2, B^2, K^2, Q^2].
struct AdevResidual {
  AdevResidual(double at_tau, double measured_adev, double rel, bool with_q)
      : tau(at_tau), adev(measured_adev), w(1.0 / (rel * measured_adev)), use_q(with_q) {}
  template <typename T>
  bool operator()(const T* c, T* r) const {
    T avar = c[0] / tau + kFlickerVar * c[1] + c[2] * tau / 3.0;
    if (use_q) avar += 3.0 * c[3] / (tau * tau);
    r[0] = (sqrt(avar + T(1e-300)) - adev) * w;
    return true;
  }
  double tau, adev, w;
  bool use_q;
};

}  // namespace

void AllanOptions::validate() const {
  if (points_per_decade < 1)
    throw std::invalid_argument("AllanOptions: points_per_decade must be >= 1");
  if (!(max_cluster_fraction > 0.0 && max_cluster_fraction <= 0.5))
    throw std::invalid_argument("AllanOptions: max_cluster_fraction = " +
                                std::to_string(max_cluster_fraction) + " must be in (0, 0.5]");
}

void AllanFitOptions::validate() const {
  if (min_cluster_samples < 1 || !(relative_error_floor >= 0.0))
    throw std::invalid_argument(
        "AllanFitOptions: min_cluster_samples must be >= 1 and relative_error_floor >= 0");
  if (min_tau_s < 0.0 || max_tau_s < 0.0 || (max_tau_s > 0.0 && max_tau_s <= min_tau_s))
    throw std::invalid_argument("AllanFitOptions: bad tau range [" + std::to_string(min_tau_s) +
                                ", " + std::to_string(max_tau_s) + "]");
}

AllanCurve allanDeviation(const std::vector<Eigen::Vector3d>& rate, double dt,
                          const AllanOptions& opt) {
  opt.validate();
  if (rate.size() < 16 || !(dt > 0.0))
    throw std::invalid_argument("allanDeviation: need >= 16 samples and dt > 0 (got " +
                                std::to_string(rate.size()) + ", dt " + std::to_string(dt) + ")");
  const std::size_t n = rate.size();
  // Cumulative angle theta_k = dt * sum_{j<k} rate_j, k = 0..n. Subtract the mean rate first to
  // keep the differences accurate (the Allan variance ignores a constant).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& r : rate) mean += r;
  mean /= static_cast<double>(n);
  std::vector<Eigen::Vector3d> theta(n + 1);
  theta[0].setZero();
  for (std::size_t k = 0; k < n; ++k) theta[k + 1] = theta[k] + (rate[k] - mean) * dt;

  std::vector<long> ms;
  const long m_max = std::max<long>(1, static_cast<long>(opt.max_cluster_fraction * n));
  if (opt.octave) {
    for (long m = 1; m <= m_max; m *= 2) ms.push_back(m);
  } else {
    const double step = std::pow(10.0, 1.0 / opt.points_per_decade);
    for (double x = 1.0; x <= m_max; x *= step) {
      const long m = std::lround(x);
      if (ms.empty() || m != ms.back()) ms.push_back(m);
    }
  }
  AllanCurve c;
  c.dt_s = dt;
  c.n = n;
  for (long m : ms) {
    const std::size_t mm = static_cast<std::size_t>(m);
    if (2 * mm >= n) break;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k + 2 * mm <= n; ++k) {
      const Eigen::Vector3d d = theta[k + 2 * mm] - 2.0 * theta[k + mm] + theta[k];
      s += d.cwiseProduct(d);
    }
    const double tau = m * dt;
    const double cnt = static_cast<double>(n - 2 * mm + 1);
    c.tau_s.push_back(tau);
    c.m.push_back(m);
    c.adev.push_back((s / (2.0 * tau * tau * cnt)).cwiseSqrt());
    c.rel_error.push_back(1.0 / std::sqrt(2.0 * (static_cast<double>(n) / m - 1.0)));
  }
  return c;
}

AllanCurve allanDeviation(const ImuSeries& imu, bool gyro, const AllanOptions& opt) {
  if (imu.size() < 16) throw std::invalid_argument("allanDeviation: need >= 16 samples");
  std::vector<Eigen::Vector3d> rate(imu.size());
  double T = 0.0;
  for (std::size_t k = 0; k < imu.size(); ++k) {
    if (!(imu[k].dt_s > 0.0))
      throw std::invalid_argument("allanDeviation: sample " + std::to_string(k) + " has dt_s <= 0");
    rate[k] = (gyro ? imu[k].dtheta_rad : imu[k].dvel_m_s) / imu[k].dt_s;
    T += imu[k].dt_s;
  }
  return allanDeviation(rate, T / static_cast<double>(imu.size()), opt);
}

double AllanFit::modelAdev(int a, double tau) const {
  const double N = terms.white_noise[a], B = terms.bias_instability[a],
               K = terms.rate_random_walk[a], Q = quantization[a];
  return std::sqrt(3.0 * Q * Q / (tau * tau) + N * N / tau + kFlickerVar * B * B +
                   K * K * tau / 3.0);
}

AllanFit fitAllanNoiseTerms(const AllanCurve& curve, const AllanFitOptions& opt) {
  opt.validate();
  AllanFit out;
  for (int a = 0; a < 3; ++a) {
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < curve.tau_s.size(); ++i) {
      const double t = curve.tau_s[i];
      if (t < opt.min_tau_s || (opt.max_tau_s > 0.0 && t > opt.max_tau_s)) continue;
      if (curve.m[i] < opt.min_cluster_samples) continue;
      if (!(curve.adev[i][a] > 0.0)) continue;
      idx.push_back(i);
    }
    const int np = opt.fit_quantization ? 4 : 3;
    if (static_cast<int>(idx.size()) < np + 1)
      throw std::invalid_argument("fitAllanNoiseTerms: only " + std::to_string(idx.size()) +
                                  " cluster times in the fit range (need " +
                                  std::to_string(np + 1) + ")");
    // Initial values: N from the first point, B from the minimum, K from the last point.
    double amin = INFINITY;
    std::size_t imin = idx[0];
    for (auto i : idx)
      if (curve.adev[i][a] < amin) {
        amin = curve.adev[i][a];
        imin = i;
      }
    const std::size_t i0 = idx.front(), i1 = idx.back();
    double c[4] = {std::pow(curve.adev[i0][a], 2) * curve.tau_s[i0] * 0.5,
                   std::pow(amin / kFlickerFactor, 2) * 0.25,
                   std::pow(curve.adev[i1][a], 2) * 3.0 / curve.tau_s[i1] * 0.1, 0.0};
    ceres::Problem problem;
    for (auto i : idx)
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<AdevResidual, 1, 4>(new AdevResidual(
              curve.tau_s[i], curve.adev[i][a],
              std::hypot(curve.rel_error[i], opt.relative_error_floor), opt.fit_quantization)),
          nullptr, c);
    if (!opt.fit_quantization) problem.SetManifold(c, new ceres::SubsetManifold(4, {3}));
    for (int k = 0; k < np; ++k) problem.SetParameterLowerBound(c, k, 0.0);
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 200;
    so.function_tolerance = 1e-12;
    so.parameter_tolerance = 1e-12;
    ceres::Solver::Summary sum;
    ceres::Solve(so, &problem, &sum);
    if (!sum.IsSolutionUsable())
      throw std::runtime_error("fitAllanNoiseTerms: Ceres failed on axis " + std::to_string(a) +
                               ": " + sum.message);
    const int dof = static_cast<int>(idx.size()) - np;
    const double chi2r = dof > 0 ? 2.0 * sum.final_cost / dof : 1.0;
    out.reduced_chi2[a] = chi2r;
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = -1;
    co.min_reciprocal_condition_number = 1e-14;
    ceres::Covariance cov(co);
    std::vector<std::pair<const double*, const double*>> blocks{{c, c}};
    double C[16] = {0};
    if (cov.Compute(blocks, &problem)) cov.GetCovarianceBlock(c, c, C);
    const double scale = std::max(1.0, chi2r);
    auto sd = [&](int k, double coeff) {
      const double var_c = std::max(0.0, C[5 * k] * scale);
      // sigma of sqrt(c): delta method, or sqrt(sigma_c) when c is at the bound 0.
      return coeff > 0.0 ? std::sqrt(var_c) / (2.0 * std::sqrt(coeff))
                         : std::sqrt(std::sqrt(var_c));
    };
    out.terms.white_noise[a] = std::sqrt(c[0]);
    out.terms.white_noise_sigma[a] = sd(0, c[0]);
    out.terms.bias_instability[a] = std::sqrt(c[1]);
    out.terms.bias_instability_sigma[a] = sd(1, c[1]);
    out.terms.rate_random_walk[a] = std::sqrt(c[2]);
    out.terms.rate_random_walk_sigma[a] = sd(2, c[2]);
    out.quantization[a] = opt.fit_quantization ? std::sqrt(c[3]) : 0.0;
    out.readoff_bias_instability[a] = amin / kFlickerFactor;
    out.tau_min_s[a] = curve.tau_s[imin];
  }
  return out;
}

}  // namespace graftnav
