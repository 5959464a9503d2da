#pragma once
// Multi-position calibration without a turntable (after Tedaldi, Pretto, Menegatti, ICRA 2014;
// own implementation): the IMU is put by hand in many static attitudes.
//
// 1. Static intervals are found by the variance detector (static_detector.h).
// 2. Accelerometer: with measured = M true + bias and M LOWER-TRIANGULAR (3 scale factors and 3
//    non-orthogonalities; the triad's absolute rotation is unobservable from norms, so the
//    calibrated frame has x along the sensor x axis and y in the sensor x-y plane), every static
//    interval k must satisfy |M^-1 (u_k - bias)| = g. Solved in Ceres for K = M^-1 (lower
//    triangular, 6) and bias (3); residual (|K (u_k - b)| - g) / sigma_k, sigma_k = the
//    interval's sigma-of-mean of |u|; covariance scaled by max(1, reduced chi-square) and
//    propagated to M by dM = -M dK M.
// 3. Gyro: bias = duration-weighted mean of the static gyro means (minus the vertical Earth rate
//    when the latitude is known; the horizontal Earth rate, <= 7.3e-5 rad/s, is not removable
//    without heading and is left in). Then K_g = M_g^-1 (full 3x3, 9 parameters, in the
//    calibrated accelerometer frame) is fitted so that integrating omega = K_g (omega_meas - b_g)
//    from the end of static interval k to the start of k+1 rotates the calibrated gravity
//    direction of k onto that of k+1: residual u_{k+1} - R^T u_k (unit vectors), R the integrated
//    rotation (body at k+1 to body at k). The Earth rotation during the few seconds of motion is
//    neglected. Weights: 1 (radian); covariance scaled by the reduced chi-square.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graftnav/calibration/calibration_result.h"
#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct MultiPositionOptions {
  StaticDetectorOptions detector;
  double gravity_m_s2 = 9.80665;  // local gravity magnitude (normal gravity when latitude known)
  double latitude_rad = 0.0;
  bool latitude_known = false;
  int min_intervals = 9;  // >= 9 (accel has 9 unknowns); fewer is an error
  // Static intervals whose gravity directions differ by less than this count as one attitude.
  double distinct_attitude_deg = 10.0;
  // With fewer distinct attitudes than 9 (e.g. a six-position session) the accelerometer
  // non-orthogonality is not observable from norms (it enters to second order for axis-aligned
  // poses): M is then fitted diagonal (scale + bias) and a note says so; fewer than 6 is an error.
  int min_distinct_for_full_accel = 9;
  bool calibrate_gyro = true;
  int max_iterations = 500;
  void validate() const;
};

struct MultiPositionResult {
  SensorCalibration accel;
  SensorCalibration gyro;
  std::vector<StaticInterval> intervals;
  double gyro_threshold_rad_s = 0.0, accel_threshold_m_s2 = 0.0;
  // RMS of |f| - g over the static intervals with the nominal input and after calibration (m/s^2).
  double accel_norm_rms_before = 0.0, accel_norm_rms_after = 0.0;
  // RMS angle (rad) between predicted and measured gravity direction over the motions, before
  // (nominal gyro, bias removed) and after.
  double gyro_angle_rms_before = 0.0, gyro_angle_rms_after = 0.0;
  bool accel_converged = false, gyro_converged = false;
  int accel_iterations = 0, gyro_iterations = 0;
  int distinct_attitudes = 0;
  bool accel_diagonal_only = false;
  std::vector<std::string> notes;
};

// `imu` holds nominally scaled increments (SI). Throws std::runtime_error naming `source` when
// fewer than min_intervals static intervals are found or the problem does not converge.
MultiPositionResult calibrateMultiPosition(const ImuSeries& imu,
                                           const MultiPositionOptions& options,
                                           const std::string& source = "multi-position data");

// Nominal count -> SI conversion for raw ADC recordings (imu_tk_xsens_calib/raw): per axis
// value_SI = (count - offset) * scale.
struct RawCountScale {
  Eigen::Vector3d accel_offset = Eigen::Vector3d::Constant(32768.0);
  Eigen::Vector3d accel_scale = Eigen::Vector3d::Constant(9.81744 / 4000.0);  // m/s^2 per count
  Eigen::Vector3d gyro_offset = Eigen::Vector3d::Constant(32768.0);
  Eigen::Vector3d gyro_scale = Eigen::Vector3d::Constant(1.0 / 6258.0);  // rad/s per count
};

// Reads the two imu_tk text files (`t ax ay az`, `t wx wy wz`, same time column) into an
// ImuSeries of increments (rate x dt, dt from consecutive stamps; the first sample uses the
// second interval). Throws std::runtime_error naming file:line on malformed or mismatched lines.
ImuSeries readRawCountPair(const std::string& accel_path, const std::string& gyro_path,
                           const RawCountScale& scale = {});

}  // namespace graftnav
