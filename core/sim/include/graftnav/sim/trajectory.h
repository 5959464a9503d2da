#pragma once
// Continuous-time truth trajectories for the simulator, with analytic derivatives.
//
// A Trajectory gives, at any time t inside [startTime_s(), endTime_s()], the geodetic position,
// the NED velocity v_n, its time derivative a_n = dv_n/dt (the derivative of the NED components
// along the path, so that dv_n/dt = C_nb f_b - (2 omega_ie_n + omega_en_n) x v_n + g_n holds,
// the same equation core/mechanization integrates), the attitude C_nb and the body rate of b
// relative to n, omega_nb_b. From these bodyRates() computes exactly what an ideal IMU senses:
//   omega_ib_b = omega_nb_b + C_bn (omega_ie_n + omega_en_n)
//   f_b        = C_bn (a_n + (2 omega_ie_n + omega_en_n) x v_n - g_n)
// with omega_ie_n, omega_en_n and normal gravity g_n from earth.h (GeographicLib, WGS-84).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct TrajectoryPoint {
  double t_s = 0.0;
  Geodetic pos;
  Eigen::Vector3d v_n = Eigen::Vector3d::Zero();         // NED velocity (m/s)
  Eigen::Vector3d a_n = Eigen::Vector3d::Zero();         // d v_n / dt (m/s^2)
  Eigen::Matrix3d C_nb = Eigen::Matrix3d::Identity();    // body to NED
  Eigen::Vector3d omega_nb_b = Eigen::Vector3d::Zero();  // rate of b relative to n, in b (rad/s)
};

// What an ideal strapdown IMU measures at one instant.
struct BodyRates {
  Eigen::Vector3d omega_ib_b = Eigen::Vector3d::Zero();  // rad/s
  Eigen::Vector3d f_b = Eigen::Vector3d::Zero();         // specific force (m/s^2)
};

// Exact ideal sensor outputs at a trajectory point (formulas in the header comment).
BodyRates bodyRates(const TrajectoryPoint& p);

// ZYX Euler angles [roll, pitch, yaw] and their time derivatives -> omega_nb_b:
//   omega_nb_b = [roll' - yaw' sin(pitch),
//                 pitch' cos(roll) + yaw' sin(roll) cos(pitch),
//                -pitch' sin(roll) + yaw' cos(roll) cos(pitch)].
Eigen::Vector3d bodyRateFromEulerRates(const Eigen::Vector3d& euler_rad,
                                       const Eigen::Vector3d& euler_rate_rad_s);

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual double startTime_s() const = 0;
  virtual double endTime_s() const = 0;
  // Throws std::out_of_range when t is outside [startTime_s(), endTime_s()] by more than 1 ms.
  virtual TrajectoryPoint at(double t_s) const = 0;

  // The truth navigation state at t (gnss_week left 0; the caller sets it).
  NavState navState(double t_s) const;
};

// Base for trajectories described in a fixed local tangent plane: NED axes of the tangent plane
// at `origin` (frame n0, fixed to the Earth). Derived classes give the position p_n0(t) (m),
// its first and second time derivatives, and the Euler angles of b relative to the LOCAL n
// frame at the current position, with their rates. at() converts exactly (through ECEF):
//   pos = geodetic(origin_e + C_e_n0 p),  v_n = C_ne C_e_n0 p',
//   a_n = C_ne C_e_n0 p'' - omega_en_n x v_n   (because d(C_ne)/dt = -[omega_en_n x] C_ne),
// so no derivative of the radii of curvature is needed and nothing is differenced numerically.
class TangentPlaneTrajectory : public Trajectory {
 public:
  struct LocalKinematics {
    Eigen::Vector3d p_n0 = Eigen::Vector3d::Zero();
    Eigen::Vector3d v_n0 = Eigen::Vector3d::Zero();
    Eigen::Vector3d a_n0 = Eigen::Vector3d::Zero();
    Eigen::Vector3d euler_rad = Eigen::Vector3d::Zero();         // roll, pitch, yaw wrt local n
    Eigen::Vector3d euler_rate_rad_s = Eigen::Vector3d::Zero();  // their time derivatives
  };

  explicit TangentPlaneTrajectory(const Geodetic& origin);
  const Geodetic& origin() const { return origin_; }

  TrajectoryPoint at(double t_s) const final;
  virtual LocalKinematics local(double t_s) const = 0;

 private:
  Geodetic origin_;
  Eigen::Vector3d origin_e_;
  Eigen::Matrix3d C_e_n0_;
};

}  // namespace graftnav
