#pragma once
// The whole lab analysis of one case (what `graftnav calibrate` runs):
//  accel: six-position (+ tilts) least squares with covariance, cross-checked against Eq. 8;
//  gyro: Eq. 9 biases, Eq. 10-11 when pos/neg pairs exist, and the joint least squares over the
//        static poses and all rate runs (the result written); without rate runs only the bias;
//  basic error signals of lab/static.txt (Eq. 12-20) and their Allan analysis;
//  fitting functions (Eq. 21) per axis from the same observations.

#include <string>
#include <vector>

#include "graftnav/calibration/allan.h"
#include "graftnav/calibration/basic_error.h"
#include "graftnav/calibration/calibration_result.h"
#include "graftnav/calibration/fitting_function.h"
#include "graftnav/calibration/gyro_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/calibration/six_position.h"

namespace graftnav {

struct LabCalibrationOptions {
  LinearModelOptions lsq;
  PolynomialFitOptions poly;
  bool allan = true;
  AllanOptions allan_curve;
  AllanFitOptions allan_fit;
  double min_allan_duration_s = 60.0;  // shorter static records get no Allan analysis (a note)
};

struct PoseNormCheck {
  std::string name;
  double raw_norm = 0.0, calibrated_norm = 0.0;  // |f| before and after calibration (m/s^2)
};

struct LabCalibrationReport {
  CalibrationResult result;
  bool has_accel = false;
  LinearModelFit accel_fit;
  Eigen::Matrix<double, 3, 4> accel_closed_form = Eigen::Matrix<double, 3, 4>::Zero();
  std::vector<LinearObservation> accel_obs;
  std::vector<PoseNormCheck> norm_checks;
  double norm_rms_before = 0.0, norm_rms_after = 0.0;  // RMS(|f| - g) over the static poses
  bool has_gyro_lsq = false;
  LinearModelFit gyro_fit;
  std::vector<LinearObservation> gyro_obs;
  bool has_eq9 = false;
  GyroBiasEstimate eq9;
  bool has_eq10 = false;
  TurnTableEstimate eq10;
  bool has_basic = false;
  BasicErrorExtraction basic;
  // Pose-to-pose drift added to the fitting-function points (pose_drift.h; zero when unknown).
  double pose_drift_window_s = 0.0, pose_drift_separation_s = 0.0;
  PoseDriftEstimate accel_pose_drift;  // m/s^2, pooled over the axes
  PoseDriftEstimate gyro_pose_drift;   // rad/s, pooled over the axes
  bool has_allan = false;
  AllanCurve gyro_allan, accel_allan;
  AllanFit gyro_allan_fit, accel_allan_fit;
  std::vector<std::string> notes;
};

// Throws std::runtime_error when the session has neither six-position poses nor a static record.
LabCalibrationReport calibrateLab(const LabData& session,
                                  const LabCalibrationOptions& options = {});

}  // namespace graftnav
