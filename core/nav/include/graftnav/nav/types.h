#pragma once
// Small value types shared by every module. Time is double GNSS seconds of week (s) everywhere.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "graftnav/nav/earth.h"

namespace graftnav {

// One IMU output sample: increments over (t_s - dt_s, t_s], resolved in the body frame (FRD).
struct ImuSample {
  double t_s = 0.0;                                      // end of the sample interval
  double dt_s = 0.0;                                     // length of the interval
  Eigen::Vector3d dtheta_rad = Eigen::Vector3d::Zero();  // integral of omega_ib_b
  Eigen::Vector3d dvel_m_s = Eigen::Vector3d::Zero();    // integral of f_b
  double temperature_degC = std::nan("");                // NaN when the file has no temperature
  bool hasTemperature() const { return !std::isnan(temperature_degC); }
};
using ImuSeries = std::vector<ImuSample>;

// Position, velocity and attitude of the body at time t_s.
struct NavState {
  double t_s = 0.0;
  Geodetic pos;
  Eigen::Vector3d v_n = Eigen::Vector3d::Zero();  // NED velocity (m/s)
  Eigen::Quaterniond q_nb = Eigen::Quaterniond::Identity();
  int gnss_week = 0;
};
using NavSeries = std::vector<NavState>;

// One GNSS position fix of the antenna.
struct GnssFix {
  double t_s = 0.0;
  Geodetic pos;
  Eigen::Vector3d std_ned_m = Eigen::Vector3d::Zero();  // 1-sigma north, east, down (= up) (m)
  int fix_type = 0;  // 0 unknown, 1 single point, 4 RTK fixed, 5 RTK float (gnss_fixtype.txt)
  int num_sv = 0;
};
using GnssSeries = std::vector<GnssFix>;

}  // namespace graftnav
