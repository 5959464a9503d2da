#pragma once
// Basic error signals (seed Eq. 12-20): the static lab record minus the theoretical output at the
// known lab attitude:
//   dtheta_err = dtheta - omega_ie_b dt,  dvel_err = dvel - f_b dt,
// with f_b = C_bn f_n, f_n = -g_n (specific force points up; the seed's Eq. 18 writes +g) and
// omega_ie_b = C_bn omega_ie_n (theoretical_output.h). The error signal is returned as an
// ImuSeries of INCREMENTS (rad, m/s) with the record's own t_s/dt_s, the form grafting consumes.
// Eq. 12: the noise level after averaging t_static seconds is D = sigma_RW / sqrt(t_static).

#include <Eigen/Core>
#include <cmath>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct BasicErrorExtraction {
  ImuSeries error;  // increments (see above)
  double duration_s = 0.0;
  Eigen::Vector3d omega_ie_b = Eigen::Vector3d::Zero();       // removed theoretical gyro output
  Eigen::Vector3d f_b = Eigen::Vector3d::Zero();              // removed theoretical specific force
  Eigen::Vector3d gyro_mean_rad_s = Eigen::Vector3d::Zero();  // mean error rate (the basic bias)
  Eigen::Vector3d accel_mean_m_s2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_std_rad_s = Eigen::Vector3d::Zero();  // per-sample std of the error rate
  Eigen::Vector3d accel_std_m_s2 = Eigen::Vector3d::Zero();
  // White-noise density estimated as std * sqrt(mean dt) (exact for white noise sampled as
  // interval means): rad/sqrt(s) and m/s/sqrt(s). The Allan fit gives a better value.
  Eigen::Vector3d gyro_white_noise = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_white_noise = Eigen::Vector3d::Zero();
  // Eq. 12 with the white-noise estimate above: noise level of the mean (rad/s, m/s^2).
  Eigen::Vector3d gyro_D = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_D = Eigen::Vector3d::Zero();
};

// gravity_m_s2 > 0 overrides normal gravity at `lab` (use 9.80665 when the latitude is unknown).
// Throws std::invalid_argument for fewer than 2 samples or dt <= 0 (naming the sample).
BasicErrorExtraction extractBasicErrors(const ImuSeries& static_imu, const Eigen::Matrix3d& C_nb,
                                        const Geodetic& lab, double gravity_m_s2 = 0.0);

// Eq. 12.
inline double averagedNoiseLevel(double white_noise_density, double t_static_s) {
  return white_noise_density / std::sqrt(t_static_s);
}

}  // namespace graftnav
