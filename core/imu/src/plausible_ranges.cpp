#include "graftnav/imu/plausible_ranges.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

constexpr double kDeg = units::kDegToRad;
constexpr double kStandardGravity = units::kStandardGravity_m_s2;
constexpr double kDegPerSecPerG = kDeg / kStandardGravity;   // deg/s/g -> rad/s per m/s^2
constexpr double kDegPerHourPerG = kDegPerSecPerG / 3600.0;  // deg/h/g -> rad/s per m/s^2

// A non-linearity of `fraction` of full scale (best-fit-line deviation of k2 x^2 over +-FS is
// k2 FS^2 / 2) as the bound on k2: 2 fraction / FS.
double curvatureBound(double fraction_of_full_scale, double full_scale) {
  return 2.0 * fraction_of_full_scale / full_scale;
}

}  // namespace

void PlausibleRanges::validate() const {
  const std::pair<const char*, double> fields[] = {
      {"gyro_scale_max", gyro_scale_max},
      {"accel_scale_max", accel_scale_max},
      {"gyro_nonorthogonality_max_rad", gyro_nonorthogonality_max_rad},
      {"accel_nonorthogonality_max_rad", accel_nonorthogonality_max_rad},
      {"gyro_scale_asymmetry_max", gyro_scale_asymmetry_max},
      {"accel_scale_asymmetry_max", accel_scale_asymmetry_max},
      {"gyro_scale_nonlinearity_max_per_rad_s", gyro_scale_nonlinearity_max_per_rad_s},
      {"accel_scale_nonlinearity_max_per_m_s2", accel_scale_nonlinearity_max_per_m_s2},
      {"g_sensitivity_max_rad_s_per_m_s2", g_sensitivity_max_rad_s_per_m_s2}};
  for (const auto& [key, v] : fields)
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument("PlausibleRanges (" + sensor_class + "): " + key +
                                  " must be positive and finite, got " + std::to_string(v));
}

PlausibleRanges plausibleRangesForClass(const std::string& c) {
  PlausibleRanges r;
  r.sensor_class = c;
  const double gyro_fs_2000 = 2000.0 * kDeg, gyro_fs_500 = 500.0 * kDeg, gyro_fs_400 = 400.0 * kDeg;
  if (c == "consumer_mems") {
    r.source =
        "consumer MEMS datasheet class (BMI160/BMI270-, ICM-20xxx-class, Xsens DOT): "
        "sensitivity +-1..3 %, cross-axis +-1..2 %, non-linearity 0.1..0.5 % FS, "
        "g-sensitivity ~0.1 deg/s/g; bounds about twice the worst";
    r.gyro_scale_max = r.accel_scale_max = 0.03;
    r.gyro_nonorthogonality_max_rad = r.accel_nonorthogonality_max_rad = 0.02;  // 2 % cross-axis
    r.gyro_scale_asymmetry_max = r.accel_scale_asymmetry_max = 0.03;
    r.gyro_scale_nonlinearity_max_per_rad_s = curvatureBound(0.01, gyro_fs_2000);
    r.accel_scale_nonlinearity_max_per_m_s2 = curvatureBound(0.01, 16.0 * kStandardGravity);
    r.g_sensitivity_max_rad_s_per_m_s2 = 0.2 * kDegPerSecPerG;
  } else if (c == "industrial_mems") {
    r.source =
        "calibrated industrial MEMS datasheet class (ADIS1646x-class): scale 0.1..0.3 %, "
        "misalignment 0.05..0.25 deg, non-linearity 0.1..0.2 % FS, g-sensitivity "
        "~0.01 deg/s/g; bounds about twice the worst";
    r.gyro_scale_max = r.accel_scale_max = 0.006;
    r.gyro_nonorthogonality_max_rad = r.accel_nonorthogonality_max_rad = 0.5 * kDeg;
    r.gyro_scale_asymmetry_max = r.accel_scale_asymmetry_max = 0.006;
    r.gyro_scale_nonlinearity_max_per_rad_s = curvatureBound(0.004, gyro_fs_500);
    r.accel_scale_nonlinearity_max_per_m_s2 = curvatureBound(0.004, 10.0 * kStandardGravity);
    r.g_sensitivity_max_rad_s_per_m_s2 = 0.02 * kDegPerSecPerG;
  } else if (c == "tactical") {
    r.source =
        "tactical FOG/RLG datasheet class (HG1700-, POS310-class): scale 100..500 ppm, "
        "misalignment 0.1..0.5 mrad, g-sensitivity 1..5 deg/h/g; bounds about twice the "
        "worst";
    r.gyro_scale_max = r.accel_scale_max = 1000e-6;
    r.gyro_nonorthogonality_max_rad = r.accel_nonorthogonality_max_rad = 1e-3;
    r.gyro_scale_asymmetry_max = r.accel_scale_asymmetry_max = 1000e-6;
    r.gyro_scale_nonlinearity_max_per_rad_s = curvatureBound(1000e-6, gyro_fs_400);
    r.accel_scale_nonlinearity_max_per_m_s2 = curvatureBound(1000e-6, 10.0 * kStandardGravity);
    r.g_sensitivity_max_rad_s_per_m_s2 = 10.0 * kDegPerHourPerG;
  } else if (c == "navigation") {
    r.source =
        "navigation-grade RLG/FOG datasheet class (POS830-class): scale 5..50 ppm, "
        "misalignment < 0.1 mrad, g-sensitivity < 0.5 deg/h/g; bounds about twice the "
        "worst";
    r.gyro_scale_max = r.accel_scale_max = 100e-6;
    r.gyro_nonorthogonality_max_rad = r.accel_nonorthogonality_max_rad = 0.2e-3;
    r.gyro_scale_asymmetry_max = r.accel_scale_asymmetry_max = 100e-6;
    r.gyro_scale_nonlinearity_max_per_rad_s = curvatureBound(100e-6, gyro_fs_400);
    r.accel_scale_nonlinearity_max_per_m_s2 = curvatureBound(100e-6, 10.0 * kStandardGravity);
    r.g_sensitivity_max_rad_s_per_m_s2 = 1.0 * kDegPerHourPerG;
  } else {
    throw std::invalid_argument("plausibleRangesForClass: unknown sensor class '" + c +
                                "' (consumer_mems, industrial_mems, tactical, navigation)");
  }
  return r;
}

std::string sensorClassForGrade(ImuGrade grade) {
  return grade == ImuGrade::kMems ? "consumer_mems" : imuGradeName(grade);
}

}  // namespace graftnav
