#pragma once
// A simulated wheel odometer (field/odometer.txt): at epochs k / rate_hz of the GNSS time, the
// truth's velocity at the odometer lever arm in the vehicle frame (model and frames:
// graftnav/estimation/vehicle_aiding.h), its forward component read with a scale error, white
// noise and an optional quantization:
//
//   v_v = C_vb (C_bn v_n + omega_nb_b x l_b),   s = q round(((1 + k) v_v.x + n) / q)
//
// (no rounding when q = 0; no noise while the vehicle stands, |v_v.x| < 1 mm/s, since a wheel at
// rest gives no pulse; a forward-only odometer reads max(s, 0)). The same for every IMU of the
// case: grafting leaves it alone.

#include <Eigen/Core>
#include <cstdint>

#include "graftnav/estimation/vehicle_aiding.h"
#include "graftnav/sim/trajectory.h"

namespace graftnav {

struct OdometerSimOptions {
  double rate_hz = 10.0;
  double scale_error = 0.0;       // k, a fraction (+0.003 = 3000 ppm fast)
  double noise_std_m_s = 0.05;    // white noise on each reading
  double quantization_m_s = 0.0;  // reading step; 0 = none
  Eigen::Vector3d lever_arm_b_m = Eigen::Vector3d::Zero();  // odometer point from the IMU, FRD
  Eigen::Vector3d mounting_rad = Eigen::Vector3d::Zero();   // roll, pitch, yaw of b in v
  bool add_noise = true;     // false: noise-free readings (the scale error stays)
  bool forward_only = true;  // readings never below zero (an unsigned wheel-speed sensor)
  void validate() const;     // throws std::invalid_argument naming the field
};

// The vehicle-frame velocity of the odometer point at a truth point.
Eigen::Vector3d odometerPointVelocity_v(const TrajectoryPoint& p, const Eigen::Matrix3d& C_vb,
                                        const Eigen::Vector3d& lever_arm_b_m);

// Readings at the epochs inside [t_begin_s, t_end_s]; noise from a stream seeded by `seed`.
OdometerSeries simulateOdometer(const Trajectory& trj, double t_begin_s, double t_end_s,
                                const OdometerSimOptions& opt, uint64_t seed);

}  // namespace graftnav
