#pragma once
// The largest error a sensor of one class can have, per error term: a fitted value beyond it is
// not that physics (the mismatch finder reports it as implausible, absorbing something else).
// SI inside; the profile files give them in unit-named keys (imu_profile_io.h, block
// `plausible_ranges:`). Bounds are about twice the worst value on datasheets of the class, so a
// sensor that meets its datasheet is always inside; they are not 1-sigma values.
//
// Classes and their source (the datasheet class; no single part number):
//   consumer_mems    phone / wearable MEMS (BMI160/BMI270-, ICM-20xxx-class chips, as inside the
//                    Xsens DOT): sensitivity tolerance +-1..3 %, cross-axis +-1..2 %,
//                    non-linearity 0.1..0.5 % of full scale (2000 deg/s, 16 g), g-sensitivity
//                    about 0.1 deg/s/g. A factory-calibrated module reaches ~1 % and < 0.5 deg.
//   industrial_mems  calibrated industrial MEMS (ADIS1646x-class): scale 0.1..0.3 %, axis
//                    misalignment 0.05..0.25 deg, non-linearity 0.1..0.2 % FS (500 deg/s,
//                    10 g), g-sensitivity about 0.01 deg/s/g.
//   tactical         FOG / RLG tactical IMUs (HG1700-, POS310-class): scale 100..500 ppm,
//                    misalignment 0.1..0.5 mrad, g-sensitivity 1..5 deg/h/g.
//   navigation       navigation-grade RLG / FOG (POS830-class): scale 5..50 ppm, misalignment
//                    below 0.1 mrad, g-sensitivity below 0.5 deg/h/g.
// A profile's grade maps to a class when the profile names none: mems -> consumer_mems (the
// widest MEMS class: a grade alone does not say the part is calibrated), tactical -> tactical,
// navigation -> navigation.

#include <string>

#include "graftnav/imu/imu_grade.h"

namespace graftnav {

struct PlausibleRanges {
  std::string sensor_class;     // consumer_mems | industrial_mems | tactical | navigation
  std::string source;           // where the bounds come from (the datasheet class)
  double gyro_scale_max = 0.0;  // |k| (fraction)
  double accel_scale_max = 0.0;
  double gyro_nonorthogonality_max_rad = 0.0;  // |N_ij|
  double accel_nonorthogonality_max_rad = 0.0;
  double gyro_scale_asymmetry_max = 0.0;  // |k_pos|, |k_neg| (fraction)
  double accel_scale_asymmetry_max = 0.0;
  double gyro_scale_nonlinearity_max_per_rad_s = 0.0;  // |k2|
  double accel_scale_nonlinearity_max_per_m_s2 = 0.0;
  double g_sensitivity_max_rad_s_per_m_s2 = 0.0;  // |G_ij|
  // Throws std::invalid_argument naming the field when a bound is not positive and finite.
  void validate() const;
};

// The class defaults above. Throws std::invalid_argument naming the class when it is unknown.
PlausibleRanges plausibleRangesForClass(const std::string& sensor_class);
// The class a profile grade maps to (see above): consumer_mems for mems, else the grade's word.
std::string sensorClassForGrade(ImuGrade grade);

}  // namespace graftnav
