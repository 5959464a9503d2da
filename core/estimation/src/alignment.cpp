#include "graftnav/estimation/alignment.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

StaticAlignment alignStatic(const ImuSeries& imu, double t_begin_s, double duration_s,
                            const Geodetic& pos, const ImuProfile& profile,
                            double max_heading_std_rad) {
  Eigen::Vector3d sum_dth = Eigen::Vector3d::Zero(), sum_dv = Eigen::Vector3d::Zero();
  double T = 0.0;
  int n = 0;
  for (const ImuSample& s : imu) {
    if (s.t_s - s.dt_s < t_begin_s - 1e-9) continue;
    if (s.t_s > t_begin_s + duration_s + 1e-9) break;
    sum_dth += s.dtheta_rad;
    sum_dv += s.dvel_m_s;
    T += s.dt_s;
    ++n;
  }
  if (n < 10) {
    throw std::invalid_argument(
        "alignStatic: only " + std::to_string(n) +
        " IMU samples in the window starting at t=" + std::to_string(t_begin_s));
  }
  const Eigen::Vector3d f = sum_dv / T, w = sum_dth / T;
  const double g = earth::gravityMagnitude(pos);
  if (std::abs(f.norm() - g) > 0.05 * g) {
    throw std::invalid_argument("alignStatic: mean specific force " + std::to_string(f.norm()) +
                                " m/s^2 differs from gravity " + std::to_string(g) +
                                ": the IMU is not at rest in the window");
  }
  StaticAlignment a;
  const Eigen::Vector2d rp = levelFromSpecificForce(f);
  const double accel_noise = profile.vrw_m_s_sqrt_s / std::sqrt(T);
  a.level_std_rad = std::hypot(profile.accel_bias_instability_m_s2, accel_noise) / g;
  // Level the mean rate with yaw 0, then yaw = atan2(-w_E', w_N').
  const Eigen::Matrix3d C_lb = dcmFromEuler({rp.x(), rp.y(), 0.0});
  const Eigen::Vector3d w_l = C_lb * w;
  const double w_h = earth::rotationRate_rad_s() * std::cos(pos.lat_rad);
  const double gyro_sigma =
      std::hypot(profile.gyro_bias_instability_rad_s, profile.arw_rad_sqrt_s / std::sqrt(T));
  a.heading_std_rad = gyro_sigma / std::max(w_h, 1e-12);
  a.euler_rad = {rp.x(), rp.y(), 0.0};
  if (a.heading_std_rad <= max_heading_std_rad) {
    a.heading_valid = true;
    a.euler_rad.z() = std::atan2(-w_l.y(), w_l.x());
  } else {
    a.note = "gyrocompassing refused: gyro bias/noise " + std::to_string(gyro_sigma) +
             " rad/s against a horizontal Earth rate of " + std::to_string(w_h) +
             " rad/s gives a heading sigma of " + std::to_string(a.heading_std_rad * kRadToDeg) +
             " deg";
  }
  return a;
}

std::optional<NavState> alignInMotion(const ImuSeries& imu, const GnssSeries& gnss,
                                      const Eigen::Vector3d& lever_arm_b_m,
                                      const MotionAlignmentOptions& o) {
  for (size_t k = 1; k + 1 < gnss.size(); ++k) {
    const GnssFix &a = gnss[k - 1], &b = gnss[k], &c = gnss[k + 1];
    if (b.t_s - a.t_s > o.max_fix_gap_s || c.t_s - b.t_s > o.max_fix_gap_s) continue;
    const Eigen::Vector3d d = earth::nedFromGeodetic(a.pos, c.pos);
    const Eigen::Vector3d v = d / (c.t_s - a.t_s);
    if (v.head<2>().norm() < o.min_speed_m_s) continue;
    // Mean specific force around t_k.
    Eigen::Vector3d sum_dv = Eigen::Vector3d::Zero();
    double T = 0.0;
    for (const ImuSample& s : imu) {
      if (s.t_s < b.t_s - 0.5 * o.level_window_s) continue;
      if (s.t_s > b.t_s + 0.5 * o.level_window_s) break;
      sum_dv += s.dvel_m_s;
      T += s.dt_s;
    }
    if (T <= 0.0) continue;
    const Eigen::Vector3d f_b = sum_dv / T;
    const Eigen::Vector2d rp = levelFromSpecificForce(f_b);
    const double yaw = std::atan2(v.y(), v.x());
    Eigen::Quaterniond q = quatFromEuler({rp.x(), rp.y(), yaw});
    if (o.compensate_acceleration) {
      // Levelling sees f_n = a_n - g_n, not -g_n: rotate the apparent vertical onto the direction
      // of f_n with a_n from the second difference of the fixes, then restore the GNSS heading.
      const Eigen::Vector3d d_ab = earth::nedFromGeodetic(b.pos, a.pos);
      const Eigen::Vector3d d_cb = earth::nedFromGeodetic(b.pos, c.pos);
      const double h1 = b.t_s - a.t_s, h2 = c.t_s - b.t_s;
      const Eigen::Vector3d a_n = 2.0 * (d_cb / h2 + d_ab / h1) / (h1 + h2);
      const Eigen::Vector3d f_n = a_n - earth::gravity_n(b.pos);
      const Eigen::Quaterniond corr =
          Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d(0, 0, -1), f_n.normalized());
      Eigen::Vector3d e = eulerFromQuat(corr * q);
      e.z() = yaw;
      q = quatFromEuler(e);
    }
    NavState st;
    st.t_s = b.t_s;
    st.v_n = v;
    st.q_nb = q;
    st.pos = earth::offsetByNed(b.pos, -(st.q_nb * lever_arm_b_m));
    return st;
  }
  return std::nullopt;
}

}  // namespace graftnav
