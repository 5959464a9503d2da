#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"

namespace graftnav {

const char* sensorName(Sensor s) { return s == Sensor::gyro ? "gyro" : "accel"; }

Sensor sensorNamed(const std::string& name) {
  if (name == sensorName(Sensor::gyro)) return Sensor::gyro;
  if (name == sensorName(Sensor::accel)) return Sensor::accel;
  throw std::invalid_argument("sensorNamed: '" + name + "' is not a single sensor (gyro, accel)");
}

TermKind termKindNamed(const std::string& name) {
  static const std::pair<const char*, TermKind> kTable[] = {
      {"constant_bias", TermKind::constant_bias},
      {"bias_instability", TermKind::bias_instability},
      {"scale_factor", TermKind::scale_factor},
      {"non_orthogonality", TermKind::non_orthogonality},
      {"g_sensitivity", TermKind::g_sensitivity},
      {"scale_asymmetry", TermKind::scale_asymmetry},
      {"scale_nonlinearity", TermKind::scale_nonlinearity},
      {"temperature_bias", TermKind::temperature_bias},
      {"temperature_scale", TermKind::temperature_scale},
      {"time_offset", TermKind::time_offset},
      {"lever_arm", TermKind::lever_arm},
      {"mounting_misalignment", TermKind::mounting_misalignment},
      {"mounting_scale_nonorthogonality", TermKind::mounting_scale_nonorthogonality},
      {"vibration_rectification", TermKind::vibration_rectification},
      {"earth_rotation_omitted", TermKind::earth_rotation_omitted},
      {"gravity_model", TermKind::gravity_model},
  };
  for (const auto& [n, kind] : kTable)
    if (name == n) return kind;
  return TermKind::other;
}

}  // namespace graftnav
