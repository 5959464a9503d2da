#pragma once
// Ideal lab sessions of the tested IMU at a fixed site (seed 2.1.2 and 2.2): static in a known
// attitude, six-position, rate table and tilts. At rest the theoretical outputs are
//   f_b = -C_bn g_n,  omega_ib_b = C_bn omega_ie_n;
// on the rate table the body turns about its own axis a (pointing up) at the constant rate w:
//   C_nb(t) = C_nb0 exp([a] w (t - t0)),  omega_ib_b = w a + C_bn(t) omega_ie_n,  f_b = -C_bn(t) g_n,
// integrated over each sample by Gauss-Legendre quadrature like the field IMU. The caller applies
// the tested IMU's error model to these ideal series.
//
// Poses (roll, pitch, yaw deg, ZYX of b in NED) chosen so that the named axis points UP (along
// -down): x_up [0, 90, 0], x_down [0, -90, 0], y_up [-90, 0, 0], y_down [90, 0, 0],
// z_up [180, 0, 0], z_down [0, 0, 0]. The rate table turns about an axis in its *_up pose.

#include <map>
#include <string>
#include <vector>

#include "graftnav/sim/trajectory.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct LabSimOptions {
  double latitude_rad = 30.53 * 0.017453292519943295;
  double longitude_rad = 114.35 * 0.017453292519943295;
  double height_m = 25.0;
  double rate_hz = 200.0;
  int quadrature_nodes = 6;
  double start_time_s = 100000.0;  // GNSS seconds of week at the start of every session
  double static_duration_s = 3600.0;
  Eigen::Vector3d static_euler_rad = Eigen::Vector3d::Zero();
  double six_position_duration_s = 60.0;  // 0: no six-position files
  std::vector<double> rate_table_rad_s = {10 * 0.017453292519943295, 30 * 0.017453292519943295,
                                          60 * 0.017453292519943295, 100 * 0.017453292519943295};
  int rate_table_turns = 1;  // whole turns per file (each sign, each axis)
  double tilt_duration_s = 60.0;
  std::map<std::string, Eigen::Vector3d> tilt_euler_rad;  // name -> roll, pitch, yaw
  // Throws std::invalid_argument naming the field; a rate whose whole turns do not span an
  // integer number of samples is an error (the file would not hold whole turns).
  void validate() const;
};

// The six poses above, name -> [roll, pitch, yaw] (rad).
std::map<std::string, Eigen::Vector3d> sixPositionPoses();

// A body at a fixed site turning about body axis `axis` (0..2) at rate_rad_s from C_nb0 at t0.
class LabTrajectory final : public Trajectory {
 public:
  LabTrajectory(const Geodetic& site, const Eigen::Matrix3d& C_nb0, int axis, double rate_rad_s,
                double t0_s, double duration_s);
  double startTime_s() const override { return t0_; }
  double endTime_s() const override { return t0_ + duration_; }
  TrajectoryPoint at(double t_s) const override;

 private:
  Geodetic site_;
  Eigen::Matrix3d C_nb0_;
  Eigen::Vector3d axis_;
  double rate_, t0_, duration_;
};

struct LabSession {
  std::string relative_path;  // inside the case, e.g. "lab/rate/z_neg_30.txt"
  ImuSeries ideal;
};

// All sessions: lab/static.txt, lab/six_position/*, lab/rate/*, lab/tilt/*.
std::vector<LabSession> simulateLabSessions(const LabSimOptions& opt);

}  // namespace graftnav
