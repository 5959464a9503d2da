#pragma once
// Test scenarios for graph/: a truth made by construction (the ideal increments are chosen, and
// the truth is their mechanization by core's Strapdown), plus IMU errors and GNSS fixes.
#include <random>
#include <vector>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/nav/rotation.h"

namespace graftnav::test {

struct Scenario {
  ImuSeries ideal;  // error-free increments
  NavSeries truth;  // truth[0] is the initial state, truth[k+1] after ideal[k]
};

// Vehicle that accelerates, weaves and turns at 200 Hz for `duration_s`. Body rates follow a
// chosen rate in n (plus the n-frame rate so the attitude tracks it), specific force follows a
// chosen NED acceleration minus gravity.
inline Scenario makeScenario(double duration_s, double rate_hz = 200.0, double speed_m_s = 10.0) {
  Scenario sc;
  NavState s;
  s.t_s = 100000.0;
  s.gnss_week = 2200;
  s.pos = {30.5 * kDegToRad, 114.4 * kDegToRad, 25.0};
  const Eigen::Vector3d euler(1.0 * kDegToRad, -2.0 * kDegToRad, 30.0 * kDegToRad);
  s.q_nb = quatFromEuler(euler);
  s.v_n = s.q_nb * Eigen::Vector3d(speed_m_s, 0, 0);
  sc.truth.push_back(s);
  Strapdown sd(s);
  const double dt = 1.0 / rate_hz;
  const size_t n = static_cast<size_t>(std::llround(duration_s * rate_hz));
  sc.ideal.reserve(n);
  sc.truth.reserve(n + 1);
  for (size_t k = 0; k < n; ++k) {
    const NavState& cur = sd.state();
    const double t = (k + 0.5) * dt;  // mid-interval, relative
    const Eigen::Matrix3d C_bn = cur.q_nb.toRotationMatrix().transpose();
    const Eigen::Vector3d fwd = cur.q_nb * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d a_n =
        fwd * (0.6 * std::sin(0.15 * t)) + Eigen::Vector3d(0, 0, 0.05 * std::sin(0.4 * t));
    const Eigen::Vector3d w_nb_b(0.03 * std::sin(0.7 * t), 0.02 * std::cos(0.5 * t),
                                 0.12 * std::sin(0.08 * t));
    const Eigen::Vector3d w_in_n =
        earth::omega_ie_n(cur.pos.lat_rad) + earth::omega_en_n(cur.pos, cur.v_n);
    ImuSample imu;
    imu.t_s = s.t_s + (k + 1) * dt;
    imu.dt_s = dt;
    imu.dtheta_rad = (w_nb_b + C_bn * w_in_n) * dt;
    imu.dvel_m_s = C_bn *
                   (a_n - earth::gravity_n(cur.pos) +
                    (2.0 * earth::omega_ie_n(cur.pos.lat_rad) + earth::omega_en_n(cur.pos, cur.v_n))
                        .cross(cur.v_n)) *
                   dt;
    sd.step(imu);
    sc.ideal.push_back(imu);
    sc.truth.push_back(sd.state());
  }
  return sc;
}

struct ImuErrors {
  Eigen::Vector3d bg_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d ba_m_s2 = Eigen::Vector3d::Zero();
  double arw_rad_sqrt_s = 0.0;
  double vrw_m_s_sqrt_s = 0.0;
};

inline ImuSeries addImuErrors(const ImuSeries& ideal, const ImuErrors& e, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  ImuSeries out = ideal;
  for (ImuSample& s : out) {
    const double sq = std::sqrt(s.dt_s);
    for (int i = 0; i < 3; ++i) {
      s.dtheta_rad(i) += e.bg_rad_s(i) * s.dt_s + e.arw_rad_sqrt_s * sq * nd(rng);
      s.dvel_m_s(i) += e.ba_m_s2(i) * s.dt_s + e.vrw_m_s_sqrt_s * sq * nd(rng);
    }
  }
  return out;
}

// GNSS at the antenna every `period_s` (on IMU epochs), with white noise of `std_m`.
inline GnssSeries makeGnss(const Scenario& sc, const Eigen::Vector3d& lever_b, double period_s,
                           double std_m, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, std_m);
  GnssSeries g;
  const double t0 = sc.truth.front().t_s;
  double next = t0 + period_s;
  for (const NavState& s : sc.truth) {
    if (s.t_s + 1e-9 < next) continue;
    next += period_s;
    GnssFix f;
    f.t_s = s.t_s;
    const Eigen::Vector3d off = s.q_nb * lever_b + Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    f.pos = earth::offsetByNed(s.pos, off);
    f.std_ned_m = Eigen::Vector3d::Constant(std_m);
    f.fix_type = 4;
    g.push_back(f);
  }
  return g;
}

}  // namespace graftnav::test
