#include "graftnav/sim/imu_simulator.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {

GaussLegendreRule gaussLegendreRule(int n) {
  if (n < 1 || n > 64) {
    throw std::invalid_argument("gaussLegendreRule: node count " + std::to_string(n) +
                                " outside [1, 64]");
  }
  GaussLegendreRule r;
  r.nodes.resize(n);
  r.weights.resize(n);
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(pi * (i + 0.75) / (n + 0.5));  // Tricomi initial guess
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const double pn = (n == 1) ? x : p1;
      const double pn1 = (n == 1) ? 1.0 : p0;
      dp = n * (x * pn - pn1) / (x * x - 1.0);
      const double dx = pn / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    // Recompute the derivative at the converged node for the weight.
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    const double pn = (n == 1) ? x : p1;
    const double pn1 = (n == 1) ? 1.0 : p0;
    dp = n * (x * pn - pn1) / (x * x - 1.0);
    r.nodes[i] = x;
    r.weights[i] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return r;
}

void IdealImuOptions::validate() const {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
    throw std::invalid_argument("IdealImuOptions: rate_hz must be > 0, got " +
                                std::to_string(rate_hz));
  }
  if (quadrature_nodes < 1 || quadrature_nodes > 64) {
    throw std::invalid_argument("IdealImuOptions: quadrature_nodes must be in [1, 64], got " +
                                std::to_string(quadrature_nodes));
  }
  if (!lever_arm_b_m.allFinite()) {
    throw std::invalid_argument("IdealImuOptions: lever_arm_b_m must be finite");
  }
}

ImuSample idealImuSample(const Trajectory& trj, double t0_s, double t1_s,
                         const GaussLegendreRule& rule, const Eigen::Vector3d& lever_arm_b_m) {
  const double half = 0.5 * (t1_s - t0_s);
  const double mid = 0.5 * (t1_s + t0_s);
  const bool arm = (lever_arm_b_m.array() != 0.0).any();
  Eigen::Vector3d dth = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
    const BodyRates r = bodyRates(trj.at(mid + half * rule.nodes[i]));
    dth += rule.weights[i] * r.omega_ib_b;
    dv += rule.weights[i] * r.f_b;
    if (arm) dv += rule.weights[i] * r.omega_ib_b.cross(r.omega_ib_b.cross(lever_arm_b_m));
  }
  ImuSample s;
  s.t_s = t1_s;
  s.dt_s = t1_s - t0_s;
  s.dtheta_rad = half * dth;
  s.dvel_m_s = half * dv;
  if (arm) {
    const Eigen::Vector3d omega0 = bodyRates(trj.at(t0_s)).omega_ib_b;
    const Eigen::Vector3d omega1 = bodyRates(trj.at(t1_s)).omega_ib_b;
    s.dvel_m_s += (omega1 - omega0).cross(lever_arm_b_m);
  }
  return s;
}

ImuSeries simulateIdealImu(const Trajectory& trj, double t_begin_s, double t_end_s,
                           const IdealImuOptions& opt,
                           const std::function<void(double)>& progress) {
  opt.validate();
  if (!(t_end_s > t_begin_s)) {
    throw std::invalid_argument("simulateIdealImu: empty time span [" + std::to_string(t_begin_s) +
                                ", " + std::to_string(t_end_s) + "]");
  }
  const GaussLegendreRule rule = gaussLegendreRule(opt.quadrature_nodes);
  const long n = static_cast<long>(std::floor((t_end_s - t_begin_s) * opt.rate_hz + 1e-6));
  ImuSeries out;
  out.reserve(static_cast<std::size_t>(n));
  const long step = std::max(1L, n / 100);
  double t_prev = t_begin_s;
  for (long k = 1; k <= n; ++k) {
    const double t = t_begin_s + static_cast<double>(k) / opt.rate_hz;
    out.push_back(idealImuSample(trj, t_prev, t, rule, opt.lever_arm_b_m));
    t_prev = t;
    if (progress && k % step == 0) progress(static_cast<double>(k) / n);
  }
  return out;
}

NavSeries sampleTruth(const Trajectory& trj, double t_begin_s, double t_end_s, double rate_hz,
                      int gnss_week) {
  if (!(rate_hz > 0.0)) {
    throw std::invalid_argument("sampleTruth: rate_hz must be > 0, got " + std::to_string(rate_hz));
  }
  const long n = static_cast<long>(std::floor((t_end_s - t_begin_s) * rate_hz + 1e-6));
  NavSeries out;
  out.reserve(static_cast<std::size_t>(n + 1));
  for (long k = 0; k <= n; ++k) {
    NavState s = trj.navState(t_begin_s + static_cast<double>(k) / rate_hz);
    s.gnss_week = gnss_week;
    out.push_back(s);
  }
  return out;
}

}  // namespace graftnav
