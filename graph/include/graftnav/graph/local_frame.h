#pragma once
// The Earth-fixed local tangent frame w in which graph/ keeps its position, velocity and attitude
// nodes: north-east-down axes at a fixed origin (the first node), origin at that point.
//   p_w  position of the IMU, metres, NED about the origin (exact, through ECEF: no flat-Earth)
//   v_w  velocity relative to the Earth, resolved in w (m/s)
//   q_wb attitude of the body (FRD) in w
// Because w is fixed to the Earth it turns with the Earth rate only: omega_iw_w = omega_ie_w, a
// constant vector; there is no transport rate (the local-level frame at the vehicle differs from
// w by the rotation C_nw(p), applied when converting to and from NavState). Normal gravity is a
// function of position, g_w(p) = C_wn(p) g_n(p).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// Gravity linearized about a point: g_w(p) ~= g0_w + G_w (p - p0_w). G is the gravity gradient
// (about 3e-6 s^-2); within the metres by which a node moves during optimization it is exact to
// far below any accelerometer's bias.
struct LinearGravity {
  Eigen::Vector3d p0_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d g0_w = Eigen::Vector3d::Zero();
  Eigen::Matrix3d G_w = Eigen::Matrix3d::Zero();
  Eigen::Vector3d at(const Eigen::Vector3d& p_w) const { return g0_w + G_w * (p_w - p0_w); }
};

class LocalFrame {
 public:
  explicit LocalFrame(const Geodetic& origin);

  const Geodetic& origin() const { return origin_; }
  Eigen::Vector3d toLocal(const Geodetic& pos) const;
  Geodetic toGeodetic(const Eigen::Vector3d& p_w) const;
  // Rotation from w to the local-level NED frame at pos.
  Eigen::Matrix3d C_nw(const Geodetic& pos) const;
  const Eigen::Vector3d& omega_ie_w() const { return omega_ie_w_; }
  Eigen::Vector3d gravity_w(const Eigen::Vector3d& p_w) const;
  LinearGravity linearGravity(const Eigen::Vector3d& p0_w) const;

  // Node values (p_w, v_w, q_wb) <-> NavState (geodetic, v_n, q_nb at the local level).
  NavState toNavState(double t_s, const Eigen::Vector3d& p_w, const Eigen::Vector3d& v_w,
                      const Eigen::Quaterniond& q_wb) const;
  void fromNavState(const NavState& s, Eigen::Vector3d* p_w, Eigen::Vector3d* v_w,
                    Eigen::Quaterniond* q_wb) const;

 private:
  Geodetic origin_;
  Eigen::Vector3d origin_e_;
  Eigen::Matrix3d C_ew_;
  Eigen::Vector3d omega_ie_w_;
};

}  // namespace graftnav
