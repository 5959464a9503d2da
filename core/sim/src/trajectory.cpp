#include "graftnav/sim/trajectory.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/nav/rotation.h"

namespace graftnav {

BodyRates bodyRates(const TrajectoryPoint& p) {
  const Eigen::Vector3d w_ie = earth::omega_ie_n(p.pos.lat_rad);
  const Eigen::Vector3d w_en = earth::omega_en_n(p.pos, p.v_n);
  const Eigen::Matrix3d C_bn = p.C_nb.transpose();
  BodyRates r;
  r.omega_ib_b = p.omega_nb_b + C_bn * (w_ie + w_en);
  r.f_b = C_bn * (p.a_n + (2.0 * w_ie + w_en).cross(p.v_n) - earth::gravity_n(p.pos));
  return r;
}

Eigen::Vector3d bodyRateFromEulerRates(const Eigen::Vector3d& e, const Eigen::Vector3d& de) {
  const double sr = std::sin(e.x()), cr = std::cos(e.x());
  const double sp = std::sin(e.y()), cp = std::cos(e.y());
  return {de.x() - de.z() * sp, de.y() * cr + de.z() * sr * cp, -de.y() * sr + de.z() * cr * cp};
}

NavState Trajectory::navState(double t_s) const {
  const TrajectoryPoint p = at(t_s);
  NavState s;
  s.t_s = t_s;
  s.pos = p.pos;
  s.v_n = p.v_n;
  s.q_nb = Eigen::Quaterniond(p.C_nb).normalized();
  return s;
}

TangentPlaneTrajectory::TangentPlaneTrajectory(const Geodetic& origin)
    : origin_(origin), origin_e_(earth::ecefFromGeodetic(origin)), C_e_n0_(earth::C_en(origin)) {}

TrajectoryPoint TangentPlaneTrajectory::at(double t_s) const {
  if (t_s < startTime_s() - 1e-3 || t_s > endTime_s() + 1e-3) {
    throw std::out_of_range("Trajectory::at: t=" + std::to_string(t_s) + " outside [" +
                            std::to_string(startTime_s()) + ", " + std::to_string(endTime_s()) +
                            "]");
  }
  const LocalKinematics k = local(t_s);
  TrajectoryPoint p;
  p.t_s = t_s;
  p.pos = earth::geodeticFromEcef(origin_e_ + C_e_n0_ * k.p_n0);
  const Eigen::Matrix3d C_n_n0 = earth::C_en(p.pos).transpose() * C_e_n0_;
  p.v_n = C_n_n0 * k.v_n0;
  p.a_n = C_n_n0 * k.a_n0 - earth::omega_en_n(p.pos, p.v_n).cross(p.v_n);
  p.C_nb = dcmFromEuler(k.euler_rad);
  p.omega_nb_b = bodyRateFromEulerRates(k.euler_rad, k.euler_rate_rad_s);
  return p;
}

}  // namespace graftnav
