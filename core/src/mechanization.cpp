#include "graftnav/core/mechanization.h"

#include <stdexcept>
#include <string>

#include "graftnav/core/rotation.h"

namespace graftnav {
namespace {

// Position after moving with constant mean velocity v_avg_n for dt, with the curvature radii
// evaluated at the mid-interval latitude and height (one fixed-point refinement).
Geodetic advancePosition(const Geodetic& p, const Eigen::Vector3d& v_avg_n, double dt) {
  Geodetic out = p;
  out.h_m = p.h_m - v_avg_n.z() * dt;
  const double h_mid = 0.5 * (p.h_m + out.h_m);
  earth::Radii r = earth::radiiOfCurvature(p.lat_rad);
  out.lat_rad = p.lat_rad + v_avg_n.x() * dt / (r.meridian_m + h_mid);
  double lat_mid = 0.5 * (p.lat_rad + out.lat_rad);
  r = earth::radiiOfCurvature(lat_mid);
  out.lat_rad = p.lat_rad + v_avg_n.x() * dt / (r.meridian_m + h_mid);
  lat_mid = 0.5 * (p.lat_rad + out.lat_rad);
  r = earth::radiiOfCurvature(lat_mid);
  out.lon_rad = p.lon_rad + v_avg_n.y() * dt / ((r.prime_vertical_m + h_mid) * std::cos(lat_mid));
  return out;
}

Geodetic midpoint(const Geodetic& a, const Geodetic& b) {
  return {0.5 * (a.lat_rad + b.lat_rad), 0.5 * (a.lon_rad + b.lon_rad), 0.5 * (a.h_m + b.h_m)};
}

}  // namespace

NavState strapdownStep(const NavState& s, const ImuSample& prev, const ImuSample& cur) {
  const double dt = cur.dt_s;
  if (!(dt > 0.0)) {
    throw std::invalid_argument("strapdownStep: sample at t=" + std::to_string(cur.t_s) +
                                " has non-positive interval dt=" + std::to_string(dt));
  }
  const Eigen::Vector3d& dth = cur.dtheta_rad;
  const Eigen::Vector3d& dv = cur.dvel_m_s;
  const Eigen::Matrix3d C_nb = s.q_nb.toRotationMatrix();

  // Body-frame velocity increment with rotation and two-sample sculling compensation.
  const Eigen::Vector3d dv_fb = dv + 0.5 * dth.cross(dv) +
                                (prev.dtheta_rad.cross(dv) + prev.dvel_m_s.cross(dth)) / 12.0;

  // First-order prediction of v_k, used only to extrapolate the mid-interval state.
  const Eigen::Vector3d wie0 = earth::omega_ie_n(s.pos.lat_rad);
  const Eigen::Vector3d wen0 = earth::omega_en_n(s.pos, s.v_n);
  const Eigen::Vector3d v_pred =
      s.v_n + C_nb * dv_fb + (earth::gravity_n(s.pos) - (2.0 * wie0 + wen0).cross(s.v_n)) * dt;
  Eigen::Vector3d v_mid = 0.5 * (s.v_n + v_pred);
  Geodetic p_mid = advancePosition(s.pos, 0.5 * (s.v_n + v_mid), 0.5 * dt);

  // Velocity update with mid-interval n-frame rotation, gravity and Coriolis.
  Eigen::Vector3d wie = earth::omega_ie_n(p_mid.lat_rad);
  Eigen::Vector3d wen = earth::omega_en_n(p_mid, v_mid);
  Eigen::Vector3d zeta = (wie + wen) * dt;
  const Eigen::Vector3d dv_f_n = C_nb * dv_fb - 0.5 * zeta.cross(C_nb * dv_fb);
  const Eigen::Vector3d dv_gc_n = (earth::gravity_n(p_mid) - (2.0 * wie + wen).cross(v_mid)) * dt;

  NavState out;
  out.t_s = cur.t_s;
  out.gnss_week = s.gnss_week;
  out.v_n = s.v_n + dv_f_n + dv_gc_n;

  // Position: trapezoidal velocity, mid-point curvature.
  const Eigen::Vector3d v_avg = 0.5 * (s.v_n + out.v_n);
  out.pos = advancePosition(s.pos, v_avg, dt);

  // Attitude: body rotation with two-sample coning, n-frame rotation at the mid-interval state.
  const Eigen::Vector3d phi = dth + prev.dtheta_rad.cross(dth) / 12.0;
  p_mid = midpoint(s.pos, out.pos);
  wie = earth::omega_ie_n(p_mid.lat_rad);
  wen = earth::omega_en_n(p_mid, v_avg);
  zeta = (wie + wen) * dt;
  out.q_nb = (quatFromRotationVector(-zeta) * s.q_nb * quatFromRotationVector(phi)).normalized();
  return out;
}

Strapdown::Strapdown(const NavState& initial) : state_(initial) {}

void Strapdown::reset(const NavState& s) {
  state_ = s;
  has_prev_ = false;
}

void Strapdown::step(const ImuSample& imu) {
  const ImuSample& prev = has_prev_ ? prev_ : imu;
  state_ = strapdownStep(state_, prev, imu);
  prev_ = imu;
  has_prev_ = true;
}

}  // namespace graftnav
