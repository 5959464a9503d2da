#pragma once
// Grafting a whole case: the lab calibration of the tested IMU (calibration/lab_calibration.h)
// turned into the inputs of grafting.h, applied to the reference field IMU.

#include <string>

#include "graftnav/calibration/calibration_result.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/sg/grafting.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// SG#2's dynamic model from one sensor's calibration: the per-axis fitting functions when the
// lab had dynamic tests (else the linear part of M: p_i(x) = b_i + M_ii x), and M's
// off-diagonal for the cross-axis terms.
SensorDynamicFit dynamicFitFromCalibration(const SensorCalibration& cal,
                                           bool use_cross_axis = true);

// Which of the seed's grafting strategies.
enum class SgStrategy {
  kBasic,  // SG#1: reference + basic error signal
  kFull,   // SG#2: reference + dynamic errors + basic error signal
};
const char* sgLabel(SgStrategy s);  // "SG1", "SG2"

// Everything grafting needs from the lab, built once and shared by every realization.
struct GraftPlan {
  BasicErrorSignal basic;
  SensorDynamicFit gyro_fit, accel_fit;
};
// Throws std::invalid_argument when the lab report has no basic error signal (no static record).
GraftPlan makeGraftPlan(const LabCalibrationReport& lab, bool use_cross_axis = true);
// One grafted series; options.start_offset_s must be resolved (>= 0) or is drawn from its seed.
ImuSeries graftSeries(const ImuSeries& reference_imu, const GraftPlan& plan, SgStrategy strategy,
                      const GraftOptions& options);

struct GraftedCase {
  ImuSeries sg1;  // SG#1 (IMU_SG1.txt): reference + basic error signal
  ImuSeries sg2;  // SG#2 (IMU_SG2.txt): reference + dynamic errors + basic error signal
  SensorDynamicFit gyro_fit, accel_fit;
  double start_offset_s = 0.0;   // where the field test starts in the tiled lab record
  double static_record_s = 0.0;  // length of the lab static record
  int tiles = 0;                 // how many record lengths the field test spans
};

struct GraftCaseOptions {
  GraftOptions graft;
  bool use_cross_axis = true;
};

// Throws std::invalid_argument when the lab report has no basic error signal (no static record).
GraftedCase graftCase(const ImuSeries& reference_imu, const LabCalibrationReport& lab,
                      const GraftCaseOptions& options = {});

}  // namespace graftnav
