#pragma once
// The files of a lab or multi-position calibration besides calibration.yaml (calibration_io.h):
// report.md (results per sensor, the checks of Eq. 8-12, the plots), the Allan curves and fits
// (allan_<sensor>.csv), the fitting-function points (fit_<sensor>.csv), the pose norms
// (pose_norms.csv) and the multi-position static intervals (static_intervals.csv). docs/outputs.md
// lists their columns.
#include <string>
#include <vector>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/calibration/multi_position.h"

namespace graftnav {

// The CSV tables of a lab calibration into out_dir (the folder exists): allan_gyro.csv and
// allan_accel.csv (with a static record), fit_accel.csv, fit_gyro.csv, pose_norms.csv.
void writeLabCalibrationTables(const std::string& out_dir, const LabData& data,
                               const LabCalibrationReport& report);

// report.md of a lab calibration of `case_dir`; its plots section lists the PNGs found in out_dir
// when `with_plots`.
std::string labCalibrationMarkdown(const std::string& case_dir, const std::string& out_dir,
                                   const LabData& data, const LabCalibrationReport& report,
                                   const LabCalibrationOptions& options, bool with_plots);

// report.md and static_intervals.csv of a multi-position calibration of `source` into out_dir;
// gravity_given: the gravity magnitude was given (else standard gravity, latitude unknown).
void writeMultiPositionReport(const std::string& out_dir, const std::string& source,
                              const MultiPositionResult& result, double gravity_m_s2,
                              bool gravity_given);

}  // namespace graftnav
