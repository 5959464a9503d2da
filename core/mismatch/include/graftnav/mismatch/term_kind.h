#pragma once
// The kind of a candidate term as a type. CandidateTerm::name is the name diagnosis.json reports
// (candidate_terms.h); the finder decides by kind, and kindOf reads the name in one place.

#include <string>

#include "graftnav/mismatch/candidate_terms.h"

namespace graftnav {

enum class TermKind {
  constant_bias,  // the nuisance
  bias_instability,
  scale_factor,
  non_orthogonality,
  g_sensitivity,
  scale_asymmetry,
  scale_nonlinearity,
  temperature_bias,
  temperature_scale,
  time_offset,
  lever_arm,
  mounting_misalignment,
  mounting_scale_nonorthogonality,
  vibration_rectification,
  earth_rotation_omitted,
  gravity_model,
  other,  // fixed helper parts (lab_quadratic_replaced, mounting_rotation_remainder, ...)
};

// The kind of a term name; TermKind::other for names that are no candidate of their own.
TermKind termKindNamed(const std::string& name);
inline TermKind kindOf(const CandidateTerm& term) { return termKindNamed(term.name); }

}  // namespace graftnav
