#pragma once
// Initial alignment for the EKF: coarse static alignment from data (roll, pitch from the mean
// specific force; heading from the Earth rate when the gyros can see it) and in-motion alignment
// for IMUs that cannot (heading from the GNSS velocity, roll and pitch from accelerometer
// levelling).

#include <optional>
#include <string>

#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/rotation.h"  // levelFromSpecificForce
#include "graftnav/nav/types.h"

namespace graftnav {

struct StaticAlignment {
  Eigen::Vector3d euler_rad = Eigen::Vector3d::Zero();  // roll, pitch, yaw (yaw 0 if refused)
  double level_std_rad = 0.0;  // 1-sigma of roll/pitch from accel noise and bias
  bool heading_valid = false;
  double heading_std_rad = 0.0;  // predicted 1-sigma from gyro bias + ARW over the window
  std::string note;              // why the heading was refused, when it was
};

// Averages the samples in [t_begin_s, t_begin_s + duration_s]. Heading from the horizontal Earth
// rate is accepted when its predicted 1-sigma (gyro bias instability and ARW / sqrt(T) against
// w_e cos(lat)) is below max_heading_std_rad. Throws std::invalid_argument when the window holds
// fewer than 10 samples or the specific force is far from g (the IMU is not at rest).
StaticAlignment alignStatic(const ImuSeries& imu, double t_begin_s, double duration_s,
                            const Geodetic& pos, const ImuProfile& profile,
                            double max_heading_std_rad = 3.0 * 0.017453292519943295);

struct MotionAlignmentOptions {
  double min_speed_m_s = 3.0;           // GNSS-derived speed needed for a heading
  double max_fix_gap_s = 1.5;           // consecutive fixes closer than this
  double level_window_s = 1.0;          // accelerometer averaging for roll/pitch
  bool compensate_acceleration = true;  // remove the GNSS-derived acceleration before levelling
};

// First GNSS epoch k with fixes k-1, k, k+1 close in time and a central-difference speed above
// min_speed: state at t_k with velocity from the central difference, heading = atan2(vE, vN),
// roll/pitch from the mean specific force around t_k (levelling; the vehicle acceleration from
// the second difference of the fixes is removed first unless disabled),
// position = antenna - C_nb lever arm. nullopt when no such epoch exists.
std::optional<NavState> alignInMotion(const ImuSeries& imu, const GnssSeries& gnss,
                                      const Eigen::Vector3d& lever_arm_b_m,
                                      const MotionAlignmentOptions& options = {});

}  // namespace graftnav
