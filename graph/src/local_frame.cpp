#include "graftnav/graph/local_frame.h"

namespace graftnav {

LocalFrame::LocalFrame(const Geodetic& origin)
    : origin_(origin),
      origin_e_(earth::ecefFromGeodetic(origin)),
      C_ew_(earth::C_en(origin)),
      omega_ie_w_(earth::omega_ie_n(origin.lat_rad)) {}

Eigen::Vector3d LocalFrame::toLocal(const Geodetic& pos) const {
  return C_ew_.transpose() * (earth::ecefFromGeodetic(pos) - origin_e_);
}

Geodetic LocalFrame::toGeodetic(const Eigen::Vector3d& p_w) const {
  return earth::geodeticFromEcef(origin_e_ + C_ew_ * p_w);
}

Eigen::Matrix3d LocalFrame::C_nw(const Geodetic& pos) const {
  return earth::C_en(pos).transpose() * C_ew_;
}

Eigen::Vector3d LocalFrame::gravity_w(const Eigen::Vector3d& p_w) const {
  const Geodetic pos = toGeodetic(p_w);
  return C_nw(pos).transpose() * earth::gravity_n(pos);
}

LinearGravity LocalFrame::linearGravity(const Eigen::Vector3d& p0_w) const {
  LinearGravity lg;
  lg.p0_w = p0_w;
  lg.g0_w = gravity_w(p0_w);
  constexpr double kStep_m = 50.0;  // central differences; gravity is smooth over kilometres
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d(k) = kStep_m;
    lg.G_w.col(k) = (gravity_w(p0_w + d) - gravity_w(p0_w - d)) / (2.0 * kStep_m);
  }
  return lg;
}

NavState LocalFrame::toNavState(double t_s, const Eigen::Vector3d& p_w, const Eigen::Vector3d& v_w,
                                const Eigen::Quaterniond& q_wb) const {
  NavState s;
  s.t_s = t_s;
  s.pos = toGeodetic(p_w);
  const Eigen::Matrix3d C = C_nw(s.pos);
  s.v_n = C * v_w;
  s.q_nb = (Eigen::Quaterniond(C) * q_wb).normalized();
  return s;
}

void LocalFrame::fromNavState(const NavState& s, Eigen::Vector3d* p_w, Eigen::Vector3d* v_w,
                              Eigen::Quaterniond* q_wb) const {
  const Eigen::Matrix3d C_wn = C_nw(s.pos).transpose();
  *p_w = toLocal(s.pos);
  *v_w = C_wn * s.v_n;
  *q_wb = (Eigen::Quaterniond(C_wn) * s.q_nb).normalized();
}

}  // namespace graftnav
