#pragma once
// An estimator's estimates of the IMU's errors at one epoch (bias and scale factor per axis):
// what it corrects the raw increments with, and what imu_errors.txt reports.
#include <Eigen/Core>

namespace graftnav {

struct ImuErrorEstimate {
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_scale = Eigen::Vector3d::Zero();   // fraction
  Eigen::Vector3d accel_scale = Eigen::Vector3d::Zero();  // fraction
};

}  // namespace graftnav
