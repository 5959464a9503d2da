#pragma once
// calibration.yaml writer and reader (the file `graftnav calibrate` writes).
//
// Layout (SI units; matrices as 3 rows of 3):
//   case: <name>
//   lab_latitude_deg: ..., gravity_m_s2: ...
//   accel:                 # and gyro:, same keys
//     method: six_position_ceres
//     M: [[..],[..],[..]]  # measured = M true + bias, M = I + S + N
//     bias: [x, y, z]      # m/s^2 (accel) or rad/s (gyro)
//     M_sigma: [[..]..]    # 1-sigma
//     bias_sigma: [..]
//     white_noise: [..]    # m/s/sqrt(s) or rad/sqrt(s)   (when Allan results exist)
//     white_noise_sigma, bias_instability (SI), bias_instability_sigma,
//     rate_random_walk (m/s^2/sqrt(s) or rad/s/sqrt(s)), rate_random_walk_sigma
//     fit: {x: {degree: 2, coeffs: [c0, c1, c2], coeffs_sigma: [...], cv_rms: ...}, y: ..., z: ...}
// Unknown keys are ignored by the reader; M and bias are required for each sensor.

#include <string>

#include "graftnav/calibration/calibration_result.h"

namespace graftnav {

// Writes `result` to `path` (throws std::runtime_error naming the path on failure).
void writeCalibrationYaml(const std::string& path, const CalibrationResult& result);

// Reads a calibration.yaml; throws std::runtime_error naming the file and key when a required key
// is missing or malformed (wrong size, NaN).
CalibrationResult readCalibrationYaml(const std::string& path);

}  // namespace graftnav
