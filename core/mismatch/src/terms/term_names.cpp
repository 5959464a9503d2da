// The name tables of the finder's types: sensors, scopes, term variants and keys. Every name
// diagnosis.json and the report write for them comes from here or from a TermSpec row.
#include <stdexcept>
#include <string>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {

namespace {
constexpr const char* kScopeNames[3] = {"gyro", "accel", "both"};
}  // namespace

const char* scopeName(SensorScope s) { return kScopeNames[index(s)]; }
const char* sensorName(Sensor s) { return scopeName(scopeOf(s)); }
const char* sensorNoun(Sensor s) { return s == Sensor::gyro ? "gyro" : "accelerometer"; }

Sensor sensorOf(SensorScope s) {
  if (s == SensorScope::both)
    throw std::invalid_argument("sensorOf: a term on both sensors has no single triad");
  return static_cast<Sensor>(s);
}

const char* variantName(TermVariant v) {
  switch (v) {
    case TermVariant::none:
      return "";
    case TermVariant::symmetric:
      return "symmetric";
    case TermVariant::replaces_lab_quadratic:
      return "replaces_lab_quadratic";
    case TermVariant::specific_force_hp_sq:
      return "specific_force_hp_sq";
    case TermVariant::angular_rate_hp_sq:
      return "angular_rate_hp_sq";
  }
  return "";
}

std::string TermKey::text() const {
  std::string s = std::string(spec ? spec->name : "?") + ":" + scopeName(sensor);
  if (variant != TermVariant::none) s += std::string(":") + variantName(variant);
  return s;
}

CandidateTerm::CandidateTerm(const TermSpec& term_spec, SensorScope scope, TermVariant v)
    : spec(&term_spec), sensor(scope), variant(v) {
  for (const TermKind k : term_spec.requires_kinds) requires_terms.push_back(termKey(k, scope));
}

TermKind CandidateTerm::kind() const { return spec->kind; }
const char* CandidateTerm::name() const { return spec->name; }
bool CandidateTerm::nuisance() const { return spec->role == TermRole::nuisance; }
bool CandidateTerm::fixed() const { return spec->fixed; }
bool CandidateTerm::slow() const { return spec->slow; }

TermKind Effect::kind() const { return spec->kind; }
const char* Effect::name() const { return spec ? spec->name : ""; }

}  // namespace graftnav
