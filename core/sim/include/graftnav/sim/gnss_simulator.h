#pragma once
// Simulated GNSS positions of the antenna: the antenna sits at the lever arm r_b (FRD, from the
// reference IMU), so its position is pos + C_nb r_b (an exact NED offset, through ECEF), plus
// white noise of the given 1-sigma north, east, up. The .pos std columns carry that sigma.

#include <Eigen/Core>
#include <cstdint>

#include "graftnav/sim/trajectory.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct GnssSimOptions {
  double rate_hz = 1.0;  // epochs at whole multiples of 1/rate_hz of the GNSS time
  Eigen::Vector3d lever_arm_b_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d noise_std_neu_m = Eigen::Vector3d(0.02, 0.02, 0.04);  // north, east, up
  bool add_noise = true;  // false: noise-free positions (the std columns still say the sigma)
  int fix_type = 4;       // written to gnss_fixtype.txt when asked (4 = RTK fixed)
  void validate() const;  // throws std::invalid_argument naming the field
};

// Antenna position for the IMU state (pos, C_nb) and lever arm r_b.
Geodetic antennaPosition(const Geodetic& pos, const Eigen::Matrix3d& C_nb,
                         const Eigen::Vector3d& lever_arm_b_m);

// Fixes at the epochs inside [t_begin_s, t_end_s]; noise from a stream seeded by `seed`.
GnssSeries simulateGnss(const Trajectory& trj, double t_begin_s, double t_end_s,
                        const GnssSimOptions& opt, uint64_t seed);

}  // namespace graftnav
