// The built-in TermSpec rows (term_spec.h): one per term of the mismatch finder. The candidates'
// order is the library's, which is the column order of every fit: a new term goes at the end of
// its group (docs/mismatch.md, "Adding a candidate term").
#include <fmt/core.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "graftnav/mismatch/term_spec.h"
#include "term_builders.h"

namespace graftnav {

namespace {

using L = ParameterLayout;
using PR = PlausibleRanges;
namespace b = term_builders;

// Units per scope (gyro, accel, both).
constexpr PerScope<const char*> kTriadUnit = {"rad/s", "m/s^2", nullptr};
constexpr PerScope<const char*> kFraction = {"1", "1", nullptr};

// size: the table of the built-in rows, one per term (a data table, not logic).
const std::vector<TermSpec>& rows() {
  static const std::vector<TermSpec> kRows = {
      // ---- the nuisance ----
      {TermKind::constant_bias,
       "constant_bias",
       TermRole::nuisance,
       TermSensors::both,
       LibraryGroup::nuisance,
       b::constantBias,
       "1 per channel (and a linear drift per channel with `linear_drift_nuisance`)",
       {}},
      // ---- candidates, in the library's order ----
      {TermKind::bias_instability,
       "bias_instability",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::bias_wander,
       b::biasInstability,
       "b(t) per axis, piecewise linear with knots every 60 s (at most 20 knots)",
       {{"sigma", L::wander_sd, kTriadUnit, {}, false, "sd of the fitted wander"},
        {"tau_s", L::knot_spacing, {"s", "s", nullptr}, {}, false, "knot spacing"}},
       /*slow=*/true},
      {TermKind::scale_factor,
       "scale_factor",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::scaleFactor,
       "k x per axis",
       {{"k", L::per_axis, kFraction, {&PR::gyro_scale_max, &PR::accel_scale_max, nullptr}}}},
      {TermKind::non_orthogonality,
       "non_orthogonality",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::nonOrthogonality,
       "off-diagonal N x (full; the accelerometer's symmetric form only through the gauge)",
       {{"N",
         L::cross_axis,
         {"rad", "rad", nullptr},
         {&PR::gyro_nonorthogonality_max_rad, &PR::accel_nonorthogonality_max_rad, nullptr}}}},
      {TermKind::scale_asymmetry,
       "scale_asymmetry",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::scaleAsymmetry,
       "d \\|x\\| per axis, with its sensor's scale_factor; variant `replaces_lab_quadratic`",
       {{"k_pos",
         L::per_axis,
         kFraction,
         {&PR::gyro_scale_asymmetry_max, &PR::accel_scale_asymmetry_max, nullptr},
         false,
         "gain for positive inputs"},
        {"k_neg",
         L::negated,
         kFraction,
         {&PR::gyro_scale_asymmetry_max, &PR::accel_scale_asymmetry_max, nullptr},
         false,
         "gain for negative inputs"},
        {"k_pos_missing", L::set_by_claims, kFraction, {}, false, "the part SG#2 lacks"},
        {"k_neg_missing", L::set_by_claims, kFraction, {}, false, "the part SG#2 lacks"}},
       /*slow=*/false,
       /*fixed=*/false,
       /*requires_kinds=*/{TermKind::scale_factor},
       /*paid_requires=*/true,
       /*shape_alternatives=*/{TermKind::scale_nonlinearity}},
      {TermKind::scale_nonlinearity,
       "scale_nonlinearity",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::scaleNonlinearity,
       "k2 x^2 per axis, with its sensor's scale_factor",
       {{"k2",
         L::per_axis,
         {"1/(rad/s)", "1/(m/s^2)", nullptr},
         {&PR::gyro_scale_nonlinearity_max_per_rad_s, &PR::accel_scale_nonlinearity_max_per_m_s2,
          nullptr},
         false,
         "the sensor's own, with the lab's c2"},
        {"k2_missing",
         L::set_by_claims,
         {"1/(rad/s)", "1/(m/s^2)", nullptr},
         {},
         false,
         "the part SG#2 lacks"}},
       /*slow=*/false,
       /*fixed=*/false,
       /*requires_kinds=*/{TermKind::scale_factor},
       /*paid_requires=*/true,
       /*shape_alternatives=*/{TermKind::scale_asymmetry}},
      {TermKind::temperature_bias,
       "temperature_bias",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::temperatureBias,
       "p (T - T_ref) per axis (T - T_sim when the simulation carries a temperature)",
       {{"per_degC", L::per_axis, {"rad/s/degC", "m/s^2/degC", nullptr}},
        {"t_ref_degC", L::reference_temperature, {"degC", "degC", nullptr}}},
       /*slow=*/true},
      {TermKind::temperature_scale,
       "temperature_scale",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::temperatureScale,
       "s (T - T_ref) x per axis",
       {{"per_degC", L::per_axis, {"1/degC", "1/degC", nullptr}}},
       /*slow=*/true},
      {TermKind::vibration_rectification,
       "vibration_rectification",
       TermRole::candidate,
       TermSensors::each_triad,
       LibraryGroup::triad,
       b::vibrationRectification,
       "c v(t) per axis, v the high-passed specific-force power; the angular-rate power for the "
       "gyro too (variants `specific_force_hp_sq`, `angular_rate_hp_sq`)",
       {{"coeff",
         L::per_axis,
         {"rad/s per level", "m/s^2 per level", nullptr},
         {},
         false,
         "per unit of the level, (m/s^2)^2 or (rad/s)^2"},
        {"regressor", L::regressor_name, {"", "", nullptr}, {}, false, "the level"}}},
      {TermKind::g_sensitivity,
       "g_sensitivity",
       TermRole::candidate,
       TermSensors::gyro,
       LibraryGroup::pair,
       b::gSensitivity,
       "G f, f the specific force at the tested IMU",
       {{"G",
         L::matrix,
         {"rad/s per m/s^2", nullptr, nullptr},
         {&PR::g_sensitivity_max_rad_s_per_m_s2, nullptr, nullptr}}}},
      {TermKind::time_offset,
       "time_offset",
       TermRole::candidate,
       TermSensors::both,
       LibraryGroup::pair,
       b::timeOffset,
       "tau u, u the chord (M x(t - p) - M x(t)) / p of the lab-calibrated response at the "
       "pivot p (mismatch-method.md, step 3)",
       {{"tau_s", L::scalar, {nullptr, nullptr, "s"}, {}, false, "late when positive"}}},
      {TermKind::lever_arm,
       "lever_arm",
       TermRole::candidate,
       TermSensors::accel,
       LibraryGroup::pair,
       b::leverArm,
       "omega_dot x r + omega x (omega x r), through the lab's slope",
       {{"r_m", L::per_axis, {nullptr, "m", nullptr}}}},
      {TermKind::mounting_misalignment,
       "mounting_misalignment",
       TermRole::candidate,
       TermSensors::both,
       LibraryGroup::pair,
       b::mountingMisalignment,
       "omega x phi and f x phi, linearized at the fitted rotation",
       {{"rotation_rad", L::per_axis, {nullptr, nullptr, "rad"}}}},
      {TermKind::earth_rotation_omitted,
       "earth_rotation_omitted",
       TermRole::candidate,
       TermSensors::gyro,
       LibraryGroup::pair,
       b::earthRotationOmitted,
       "C_bn omega_ie_n, coefficient fixed at 1 (simulated references only)",
       {},
       /*slow=*/true,
       /*fixed=*/true,
       /*requires_kinds=*/{TermKind::bias_instability}},
      {TermKind::gravity_model,
       "gravity_model",
       TermRole::candidate,
       TermSensors::accel,
       LibraryGroup::pair,
       b::gravityModel,
       "-C_bn [0 0 1] dg, dg the true minus the simulated gravity (simulated references only)",
       {{"delta_g_m_s2", L::scalar, {nullptr, "m/s^2", nullptr}}},
       /*slow=*/true,
       /*fixed=*/false,
       /*requires_kinds=*/{TermKind::bias_instability}},
      // ---- fixed parts, built with their candidate ----
      {TermKind::lab_quadratic_replaced,
       "lab_quadratic_replaced",
       TermRole::part,
       TermSensors::each_triad,
       LibraryGroup::not_built,
       nullptr,
       "-c2 x^2, SG#2's lab quadratic, taken out with scale_asymmetry:replaces_lab_quadratic",
       {},
       /*slow=*/false,
       /*fixed=*/true},
      {TermKind::mounting_rotation_remainder,
       "mounting_rotation_remainder",
       TermRole::part,
       TermSensors::both,
       LibraryGroup::not_built,
       nullptr,
       "the rotation's departure from its linearization at the pivot",
       {},
       /*slow=*/false,
       /*fixed=*/true},
      {TermKind::lab_curvature_known,
       "lab_curvature_known",
       TermRole::part,
       TermSensors::each_triad,
       LibraryGroup::not_built,
       nullptr,
       "c2 x^2, the lab's quadratic less the asymmetry's fold in it (the asymmetry's own gains)",
       {},
       /*slow=*/false,
       /*fixed=*/true},
      // ---- reported by the claim stages ----
      {TermKind::mounting_scale_nonorthogonality,
       "mounting_scale_nonorthogonality",
       TermRole::reported,
       TermSensors::both,
       LibraryGroup::not_built,
       nullptr,
       "E_s x_s per sensor, when the record cannot split rotation, N and k",
       {{"E_gyro",
         L::matrix,
         {nullptr, nullptr, "1"},
         {nullptr, nullptr, &PR::gyro_scale_max},
         /*diagonal_only=*/true},
        {"E_accel",
         L::matrix,
         {nullptr, nullptr, "1"},
         {nullptr, nullptr, &PR::accel_scale_max},
         /*diagonal_only=*/true}}},
      {TermKind::quantization,
       "quantization",
       TermRole::reported,
       TermSensors::each_triad,
       LibraryGroup::not_built,
       nullptr,
       "a value lattice of the tested increments beyond the printed resolution",
       {{"step", L::per_axis, {"rad", "m/s", nullptr}, {}, false, "per sample"}}},
  };
  return kRows;
}

}  // namespace

const std::vector<const TermSpec*>& builtInTermSpecs() {
  static const std::vector<const TermSpec*> kSpecs = [] {
    std::vector<const TermSpec*> out;
    for (const TermSpec& s : rows()) out.push_back(&s);
    return out;
  }();
  return kSpecs;
}

const TermSpec& termSpec(TermKind kind) {
  if (kind != TermKind::generic)
    for (const TermSpec& s : rows())
      if (s.kind == kind) return s;
  throw std::invalid_argument("termSpec: TermKind::generic names no single row");
}

const char* termName(TermKind kind) { return termSpec(kind).name; }

TermKey termKey(TermKind kind, SensorScope scope, TermVariant variant) {
  return TermKey{&termSpec(kind), scope, variant};
}

const char* unitOf(const ParameterSpec& p, SensorScope scope) { return p.unit[index(scope)]; }

double PlausibleRanges::*boundOf(const ParameterSpec& p, SensorScope scope) {
  return p.bound[index(scope)];
}

}  // namespace graftnav
