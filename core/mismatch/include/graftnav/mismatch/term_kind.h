#pragma once
// What a candidate term is, as types: its kind, its variant and its key. Each kind has one
// TermSpec (term_spec.h), which holds its name; the finder decides by kind and key, and names
// appear only in what it writes.

#include <string>

#include "graftnav/mismatch/sensor.h"

namespace graftnav {

struct TermSpec;

enum class TermKind {
  // The nuisance and the candidates, in the library's order (term_spec.h).
  constant_bias,
  bias_instability,
  scale_factor,
  non_orthogonality,
  scale_asymmetry,
  scale_nonlinearity,
  temperature_bias,
  temperature_scale,
  vibration_rectification,
  g_sensitivity,
  time_offset,
  lever_arm,
  mounting_misalignment,
  earth_rotation_omitted,
  gravity_model,
  // Fixed parts a candidate's builder adds with it (never selected or claimed alone).
  lab_quadratic_replaced,
  mounting_rotation_remainder,
  lab_curvature_known,
  // Reported by the claim stages, not columns of the library.
  mounting_scale_nonorthogonality,
  quantization,
  // A term no stage treats apart (no gate or claim rule of its own): its TermSpec row alone
  // defines it, and a term added to the finder needs no kind of its own unless a stage must
  // test for it (docs/mismatch.md, "Adding a candidate term").
  generic,
};

// What tells two terms of one kind on one scope apart.
enum class TermVariant {
  none,
  symmetric,               // non_orthogonality of the accelerometer, N_ij = N_ji (the gauge)
  replaces_lab_quadratic,  // scale_asymmetry that takes SG#2's lab quadratic out
  specific_force_hp_sq,    // vibration_rectification on the specific-force vibration level
  angular_rate_hp_sq,      // ... on the angular-rate vibration level
};

// The variant's name in keys and diagnosis.json ("" for none; the vibration levels are
// VibrationRegressor names, imu_error_terms.h).
const char* variantName(TermVariant v);

// A term's identity in a library: its spec, the sensor(s) it acts on and its variant.
struct TermKey {
  const TermSpec* spec = nullptr;
  SensorScope sensor = SensorScope::both;
  TermVariant variant = TermVariant::none;
  bool operator==(const TermKey& o) const {
    return spec == o.spec && sensor == o.sensor && variant == o.variant;
  }
  bool operator!=(const TermKey& o) const { return !(*this == o); }
  // "name:sensor[:variant]", as the selection log and diagnosis.json write it.
  std::string text() const;
};

}  // namespace graftnav
