#pragma once
// Small synthetic lab signals with known errors for the calibration tests (test-local; built from
// the conventions of rotation.h / earth.h: at rest f_b = -C_bn g_n, omega_ib_b = C_bn omega_ie_n).
#include <Eigen/Core>
#include <cmath>
#include <random>

#include "graftnav/calibration/theoretical_output.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/nav/types.h"

namespace graftnav::test {

struct SynthErrors {
  Eigen::Matrix3d M_a = Eigen::Matrix3d::Identity(), M_g = Eigen::Matrix3d::Identity();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero(), b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d k2_a = Eigen::Vector3d::Zero(), k2_g = Eigen::Vector3d::Zero();  // y += k2 x^2
  double white_a = 0.0, white_g = 0.0;  // densities: m/s/sqrt(s), rad/sqrt(s)
};

// Applies the errors to one ideal sample (mean rates over dt) with a random source.
class SynthSensor {
 public:
  SynthSensor(const SynthErrors& e, unsigned seed) : e_(e), rng_(seed) {}
  ImuSample measure(double t, double dt, const Eigen::Vector3d& w, const Eigen::Vector3d& f) {
    ImuSample s;
    s.t_s = t;
    s.dt_s = dt;
    Eigen::Vector3d wm = e_.M_g * w + e_.b_g + e_.k2_g.cwiseProduct(w.cwiseAbs2());
    Eigen::Vector3d fm = e_.M_a * f + e_.b_a + e_.k2_a.cwiseProduct(f.cwiseAbs2());
    for (int i = 0; i < 3; ++i) {
      wm[i] += e_.white_g / std::sqrt(dt) * n_(rng_);
      fm[i] += e_.white_a / std::sqrt(dt) * n_(rng_);
    }
    s.dtheta_rad = wm * dt;
    s.dvel_m_s = fm * dt;
    return s;
  }

 private:
  SynthErrors e_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n_{0.0, 1.0};
};

inline Geodetic labSite() { return {30.53 * kDegToRad, 114.35 * kDegToRad, 25.0}; }

// Static record at attitude C_nb.
inline ImuSeries synthStatic(SynthSensor& sensor, const Eigen::Matrix3d& C_nb, const Geodetic& lab,
                             double duration_s, double rate_hz, double t0 = 1000.0) {
  const double dt = 1.0 / rate_hz;
  const auto n = static_cast<std::size_t>(std::llround(duration_s * rate_hz));
  const Eigen::Vector3d w = staticEarthRate_b(C_nb, lab.lat_rad);
  const Eigen::Vector3d f = staticSpecificForce_b(C_nb, lab);
  ImuSeries out;
  out.reserve(n);
  for (std::size_t k = 1; k <= n; ++k) out.push_back(sensor.measure(t0 + k * dt, dt, w, f));
  return out;
}

// Turn about body axis `axis` (pointing up, pose C_nb0) at sign*rate for `turns` whole turns.
inline ImuSeries synthRateRun(SynthSensor& sensor, const Eigen::Matrix3d& C_nb0, int axis, int sign,
                              double rate_rad_s, int turns, const Geodetic& lab, double rate_hz,
                              double t0 = 1000.0) {
  const double T = 2.0 * M_PI * turns / rate_rad_s;
  const auto n = static_cast<std::size_t>(std::llround(T * rate_hz));
  const double dt = T / n;
  const Eigen::Vector3d a = Eigen::Vector3d::Unit(axis);
  const Eigen::Vector3d g_n = earth::gravity_n(lab);
  const Eigen::Vector3d wie_n = earth::omega_ie_n(lab.lat_rad);
  ImuSeries out;
  for (std::size_t k = 1; k <= n; ++k) {
    // Two-point Gauss average of the Earth rate and gravity over the sample.
    Eigen::Vector3d we = Eigen::Vector3d::Zero(), f = Eigen::Vector3d::Zero();
    for (double c : {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)}) {
      const double t = (k - 0.5 + 0.5 * c) * dt;
      const Eigen::Matrix3d C = C_nb0 * dcmFromRotationVector(a * sign * rate_rad_s * t);
      we += 0.5 * C.transpose() * wie_n;
      f += -0.5 * C.transpose() * g_n;
    }
    out.push_back(sensor.measure(t0 + k * dt, dt, a * sign * rate_rad_s + we, f));
  }
  return out;
}

inline Eigen::Matrix3d randomSmall(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Eigen::Matrix3d m;
  for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = n(rng);
  return m;
}

}  // namespace graftnav::test
