#pragma once
// Truth by construction for filter tests and the EKF benchmark: ideal increments are chosen
// (a car-like drive: speed and heading profiles, level), mechanized with core's Strapdown, and
// that mechanized trajectory IS the truth, exactly consistent with the increments. Errors
// (bias, scale factor, white noise) and GNSS noise at the lever arm are then added.

#include <cmath>
#include <random>

#include "graftnav/nav/earth.h"
#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/filters/ins_error_model.h"

namespace graftnav::test {

// A state at speed with a non-trivial attitude, the linearization point of the Jacobian tests.
inline NavState movingState() {
  NavState s;
  s.t_s = 1000.0;
  s.pos = {30.5 * kDegToRad, 114.3 * kDegToRad, 100.0};
  s.v_n = {15.0, 5.0, -0.5};
  s.q_nb = quatFromEuler({0.05, -0.03, 1.0});
  return s;
}

// The body rate a measured `omega_ib_b` implies under the error state x: with the gyro bias and
// scale-factor errors of x added, as the filter's measurement models see it.
inline Eigen::Vector3d perturbedBodyRate(const Eigen::Vector3d& omega_ib_b, const ErrorState& x) {
  return omega_ib_b + x.segment<3>(ekf::kGyroBias) +
         omega_ib_b.cwiseProduct(x.segment<3>(ekf::kGyroScale));
}

struct Scenario {
  ImuSeries ideal;  // error-free increments
  NavSeries truth;  // at t0 and every IMU epoch
  NavState initial;
};

// Drive of `duration_s` at `rate_hz`: speed ramps to 10 m/s, then varies by +-3 m/s; the heading
// rate swings +-0.15 rad/s; small pitch/roll oscillations excite the tilt and scale states.
inline Scenario makeDrive(double duration_s, double rate_hz, double t0_s = 100000.0) {
  Scenario sc;
  NavState s;
  s.t_s = t0_s;
  s.gnss_week = 2100;
  s.pos = {30.5 * kDegToRad, 114.3 * kDegToRad, 30.0};
  s.v_n.setZero();
  s.q_nb = quatFromEuler({0.0, 0.0, 0.3});
  sc.initial = s;
  const double dt = 1.0 / rate_hz;
  const auto n = static_cast<size_t>(std::llround(duration_s * rate_hz));
  sc.ideal.reserve(n);
  sc.truth.reserve(n + 1);
  sc.truth.push_back(s);
  Strapdown sd(s);
  auto speedRate = [](double t) {  // dV/dt
    return t < 20.0 ? 0.5 : 3.0 * (2 * M_PI / 25.0) * std::cos(2 * M_PI * (t - 20.0) / 25.0);
  };
  for (size_t k = 1; k <= n; ++k) {
    const double tm = (k - 0.5) * dt;  // mid-interval, relative time
    const NavState& c = sd.state();
    const Eigen::Matrix3d C_nb = c.q_nb.toRotationMatrix();
    const Eigen::Vector3d eul = eulerFromQuat(c.q_nb);
    const double yaw = eul.z();
    const Eigen::Vector3d a_n(speedRate(tm) * std::cos(yaw), speedRate(tm) * std::sin(yaw), 0.0);
    const Eigen::Vector3d w_ie = earth::omega_ie_n(c.pos.lat_rad);
    const Eigen::Vector3d w_en = earth::omega_en_n(c.pos, c.v_n);
    // Heading turn from the velocity direction (so the car drives forward) and a keep-level term.
    const Eigen::Vector3d f_n = a_n - earth::gravity_n(c.pos) + (2.0 * w_ie + w_en).cross(c.v_n);
    const double yaw_rate = tm < 20.0 ? 0.0 : 0.15 * std::sin(2 * M_PI * (tm - 20.0) / 40.0);
    // Rotate the velocity with the heading: centripetal acceleration.
    const Eigen::Vector3d a_c = yaw_rate * Eigen::Vector3d(-c.v_n.y(), c.v_n.x(), 0.0);
    const Eigen::Vector3d osc(0.02 * std::sin(2 * M_PI * tm / 7.0) - 0.5 * eul.x(),
                              0.015 * std::cos(2 * M_PI * tm / 11.0) - 0.5 * eul.y(), yaw_rate);
    const Eigen::Vector3d w_nb_b = osc;  // small roll/pitch oscillations, levelled, yaw rate
    ImuSample imu;
    imu.t_s = t0_s + k * dt;
    imu.dt_s = dt;
    imu.dvel_m_s = C_nb.transpose() * (f_n + a_c) * dt;
    imu.dtheta_rad = (C_nb.transpose() * (w_ie + w_en) + w_nb_b) * dt;
    sd.step(imu);
    NavState t = sd.state();
    t.gnss_week = s.gnss_week;
    sc.truth.push_back(t);
    sc.ideal.push_back(imu);
  }
  return sc;
}

struct InjectedErrors {
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_scale = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_scale = Eigen::Vector3d::Zero();
};

// Sensor errors: meas = (1 + s) ideal + b dt + white noise (ARW, VRW). With gauss_markov, the
// biases and scale factors start at the injected values and then evolve as the first-order
// Gauss-Markov processes of the profile (exact discretization), i.e. exactly the filter's model.
inline ImuSeries corrupt(const ImuSeries& ideal, const InjectedErrors& e0, const ImuProfile& p,
                         unsigned seed, bool gauss_markov = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  InjectedErrors e = e0;
  auto gm = [&](Eigen::Vector3d& x, double sigma, double T, double dt) {
    if (!(T > 0.0) || sigma <= 0.0) return;
    const double a = std::exp(-dt / T), w = sigma * std::sqrt(1.0 - a * a);
    for (int i = 0; i < 3; ++i) x[i] = a * x[i] + w * nd(rng);
  };
  ImuSeries out = ideal;
  for (ImuSample& s : out) {
    if (gauss_markov) {
      gm(e.gyro_bias_rad_s, p.gyro_bias_instability_rad_s, p.gyro_bias_corr_time_s, s.dt_s);
      gm(e.accel_bias_m_s2, p.accel_bias_instability_m_s2, p.accel_bias_corr_time_s, s.dt_s);
      gm(e.gyro_scale, p.gyro_scale_std, p.scale_corr_time_s, s.dt_s);
      gm(e.accel_scale, p.accel_scale_std, p.scale_corr_time_s, s.dt_s);
    }
    const double sq = std::sqrt(s.dt_s);
    const Eigen::Vector3d ng(nd(rng), nd(rng), nd(rng)), na(nd(rng), nd(rng), nd(rng));
    s.dtheta_rad = s.dtheta_rad + e.gyro_scale.cwiseProduct(s.dtheta_rad) +
                   e.gyro_bias_rad_s * s.dt_s + p.arw_rad_sqrt_s * sq * ng;
    s.dvel_m_s = s.dvel_m_s + e.accel_scale.cwiseProduct(s.dvel_m_s) + e.accel_bias_m_s2 * s.dt_s +
                 p.vrw_m_s_sqrt_s * sq * na;
  }
  return out;
}

// GNSS antenna fixes every `every` IMU epochs (offset_s added to the time, truth interpolated
// linearly in position), NED noise of sigma_m.
inline GnssSeries makeGnss(const NavSeries& truth, const Eigen::Vector3d& lever_b_m, int every,
                           double sigma_m, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  GnssSeries g;
  for (size_t k = static_cast<size_t>(every); k < truth.size(); k += static_cast<size_t>(every)) {
    GnssFix f;
    f.t_s = truth[k].t_s;
    const Eigen::Vector3d noise(nd(rng), nd(rng), nd(rng));
    f.pos = earth::offsetByNed(antennaPosition(truth[k], lever_b_m), sigma_m * noise);
    f.std_ned_m.setConstant(sigma_m);
    f.fix_type = 4;
    g.push_back(f);
  }
  return g;
}

inline ImuProfile tacticalProfile() {
  ImuProfile p;
  p.name = "tactical-test";
  p.grade = ImuGrade::kTactical;
  p.arw_rad_sqrt_s = 0.05 * kDegToRad / 60.0;
  p.vrw_m_s_sqrt_s = 0.1 / 60.0;
  p.gyro_bias_instability_rad_s = 0.5 * kDegToRad / 3600.0;
  p.accel_bias_instability_m_s2 = 0.5e-3 * 9.80665;
  p.gyro_scale_std = p.accel_scale_std = 300e-6;
  return p;
}

inline ImuProfile memsProfile() {
  ImuProfile p;
  p.name = "mems-test";
  p.grade = ImuGrade::kMems;
  p.arw_rad_sqrt_s = 0.15 * kDegToRad / 60.0;
  p.vrw_m_s_sqrt_s = 0.06 / 60.0;
  p.gyro_bias_instability_rad_s = 10.0 * kDegToRad / 3600.0;
  p.accel_bias_instability_m_s2 = 1e-3 * 9.80665;
  p.gyro_scale_std = p.accel_scale_std = 1000e-6;
  return p;
}

}  // namespace graftnav::test
