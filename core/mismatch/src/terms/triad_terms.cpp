// Builders of the terms of one sensor triad (term_builders.h), and of the nuisance. Each appends
// its term (and the term's fixed parts or variants) to the library for the triad it is given.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "graftnav/mismatch/term_spec.h"
#include "term_builders.h"

namespace graftnav::term_builders {

namespace {

// Column acting on one channel only.
RegressorColumn singleChannel(int channel, const Eigen::VectorXd& v) {
  RegressorColumn c;
  c.channel[channel] = v;
  return c;
}

}  // namespace

// Nuisance: constant bias and linear drift per channel.
void constantBias(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                  std::vector<CandidateTerm>* out) {
  const int n = ctx.n;
  CandidateTerm t(spec, scope);
  t.explanation =
      "turn-on bias of the field run differing from the lab, and its linear drift "
      "over the record (nuisance, not claimed)";
  for (int c = 0; c < kMismatchChannels; ++c)
    t.columns.push_back(singleChannel(c, Eigen::VectorXd::Ones(n)));
  if (ctx.opt.linear_drift_nuisance) {
    const Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
    for (int c = 0; c < kMismatchChannels; ++c) t.columns.push_back(singleChannel(c, ramp));
  }
  out->push_back(std::move(t));
}

// Hat functions at knots 0, d, 2d, ... (the last knot at the end); interior knots only.
void biasInstability(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                     std::vector<CandidateTerm>* out) {
  const CandidateLibraryOptions& opt = ctx.opt;
  const int n = ctx.n;
  const double span_s = ctx.span_s;
  const Sensor s = sensorOf(scope);
  const double knot_s = std::max(opt.knot_spacing_s, span_s / (opt.max_knots - 1));
  const int knots = std::max(2, static_cast<int>(std::ceil(span_s / knot_s - 1e-9)) + 1);
  const double spacing = span_s / (knots - 1);
  CandidateTerm t(spec, scope);
  t.knot_spacing_s = spacing;
  t.explanation = std::string("the ") + sensorName(s) +
                  " bias wanders during the field run more than the lab record shows "
                  "(piecewise-linear bias, knots every " +
                  std::to_string(static_cast<int>(std::round(spacing))) + " s)";
  // The first knot is spanned by the nuisance constant, the last one too with a linear drift.
  const int last = opt.linear_drift_nuisance ? knots - 1 : knots;
  if (last <= 1) return;
  // Knot k's hat is non-zero on bins whose middles lie within one spacing of it: only those bins
  // (and one of margin on each side, where it is exactly zero) are stored.
  const double bins_per_knot = spacing / ctx.x().grid.bin_s;
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 1; k < last; ++k) {
      const int lo =
          std::clamp(static_cast<int>(std::floor((k - 1) * bins_per_knot - 0.5)) - 1, 0, n);
      const int hi =
          std::clamp(static_cast<int>(std::ceil((k + 1) * bins_per_knot - 0.5)) + 2, lo, n);
      Eigen::VectorXd v(hi - lo);
      for (int i = lo; i < hi; ++i) {
        const double u = (i + 0.5) * ctx.x().grid.bin_s / spacing - k;  // knot k at u = 0
        v(i - lo) = std::max(0.0, 1.0 - std::abs(u));
      }
      RegressorColumn col = singleChannel(firstChannel(s) + axis, v);
      col.first_row = lo;
      col.grid_rows = n;
      t.columns.push_back(std::move(col));
    }
  }
  out->push_back(std::move(t));
}

void scaleFactor(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                 std::vector<CandidateTerm>* out) {
  const Sensor s = sensorOf(scope);
  const Eigen::MatrixX3d& u = ctx.triad[s].u;
  CandidateTerm t(spec, scope);
  t.explanation = std::string("the ") + sensorName(s) +
                  " gain differs from the simulated one (output = (1 + k) input)";
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(firstChannel(s) + a, u.col(a)));
  out->push_back(std::move(t));
}

// The full cross-axis matrix; for the accelerometer also its symmetric form, the gauge of the
// selection's last step (term_selection.h, step 4): both full non-orthogonalities together span
// a rotation common to both triads, which is the mounting's; re-expressed with a
// mounting_misalignment, the accelerometer triad keeps its symmetric cross-axis part,
// N_ij = N_ji (it defines the body frame), and the gyro's full N the rotation of the gyro triad
// relative to it. The symmetric form is never selected on its own.
void nonOrthogonality(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                      std::vector<CandidateTerm>* out) {
  const Sensor s = sensorOf(scope);
  const int c0 = firstChannel(s);
  const Eigen::MatrixX3d& u = ctx.triad[s].u;
  CandidateTerm t(spec, scope);
  t.explanation = std::string("the ") + sensorName(s) +
                  " axes are not perpendicular: each axis picks up a fraction of the others";
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) t.columns.push_back(singleChannel(c0 + i, u.col(j)));
  out->push_back(std::move(t));
  if (s != Sensor::accel) return;
  CandidateTerm sym(spec, scope, TermVariant::symmetric);
  sym.gauge_only = true;
  sym.explanation =
      "the accelerometer axes are not perpendicular: symmetric cross-axis "
      "coupling (the rotation common to both triads is the mounting's)";
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      RegressorColumn col;
      col.channel[c0 + i] = u.col(j);
      col.channel[c0 + j] = u.col(i);
      sym.columns.push_back(col);
    }
  out->push_back(std::move(sym));
}

// One parameter per axis, the half-difference d of the gains per sign (output = input + d |input|,
// so k_pos - k_neg = 2 d); their mean is scale_factor's. With both gains as parameters the term
// paid three extra parameters for the mean, which a lab-grafted simulation already holds, and lost
// to scale_nonlinearity's x^2 (the other even function) on random cases with an asymmetry 1.4-3x
// its detection limit. Measured with its sensor's scale factor (marginality, as for
// scale_nonlinearity: where the input keeps one sign (f_z ~ -g) |x| is -x, a gain; measured
// without the scale factor the term claimed that gain past the scale factor's lab gate,
// random_11_15: an accelerometer quadratic's slope at -g, 7 sigma on k_neg z, named as an
// asymmetry).
//
// When SG#2 grafts a lab c2 on the sensor, a variant replaces the lab quadratic: r_i = d_i |x_i|
// plus the fixed part lab_quadratic_replaced, -c2_i x_i^2. The lab's +-g poses (the rate table's
// +-turns) see an asymmetric gain d |x| as c2 x^2 with c2 ~ d / g, so SG#2 carries a quadratic
// the sensor does not have; on the field's small inputs the plain |x| column took up -c2 x^2 and
// the lab's c2 was then claimed as the sensor's non-linearity (CRN random_14_26). The two
// asymmetry terms exclude each other.
void scaleAsymmetry(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                    std::vector<CandidateTerm>* out) {
  const Sensor s = sensorOf(scope);
  const std::string sensor = sensorName(s);
  const int c0 = firstChannel(s);
  const TriadInputs& in = ctx.triad[s];
  CandidateTerm t(spec, scope);
  t.explanation = "the " + sensor + " gain differs for positive and negative inputs";
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(c0 + a, in.u_abs.col(a)));
  const Eigen::Vector3d& c2 =
      s == Sensor::gyro ? ctx.in.gyro_response_c2 : ctx.in.accel_response_c2;
  if (!(c2.array() != 0.0).any()) {
    out->push_back(std::move(t));
    return;
  }
  CandidateTerm part(termSpec(TermKind::lab_quadratic_replaced), scope);
  part.explanation =
      "SG#2's lab quadratic of the " + sensor + ", taken out where the asymmetry replaces it";
  RegressorColumn col;
  for (int a = 0; a < 3; ++a)
    if (c2(a) != 0.0) col.channel[c0 + a] = -c2(a) * in.u_sq.col(a);
  part.columns.push_back(col);
  CandidateTerm alt = t;
  alt.variant = TermVariant::replaces_lab_quadratic;
  alt.explanation +=
      "; the lab's quadratic in SG#2 is this asymmetry as the lab saw it "
      "(SG#3 takes it out)";
  part.part_of = alt.key();
  alt.requires_terms.push_back(part.key());
  alt.excludes = {t.key()};
  t.excludes = {alt.key()};
  out->push_back(std::move(t));
  out->push_back(std::move(alt));
  out->push_back(std::move(part));
}

// Marginality: the quadratic is tested, and fitted, with the linear term of the same sensor in
// the model. Without it x^2 stands in for a gain wherever the input keeps one sign around a large
// mean (f_z ~ -g: x^2 = -2 g x - g^2 + (x + g)^2), and under common random numbers an
// accelerometer k2 was claimed on the null case after backward elimination had dropped the scale
// factor it was imitating.
void scaleNonlinearity(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                       std::vector<CandidateTerm>* out) {
  const Sensor s = sensorOf(scope);
  const Eigen::MatrixX3d& u_sq = ctx.triad[s].u_sq;
  CandidateTerm t(spec, scope);
  t.explanation =
      std::string("the ") + sensorName(s) + " input-output line bends: output = input + k2 input^2";
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(firstChannel(s) + a, u_sq.col(a)));
  out->push_back(std::move(t));
}

namespace {

// The tested temperature about its mean, when it spans enough for the temperature terms.
struct TemperatureSpan {
  double t_ref_degC = 0.0;  // the tested temperature's mean
  Eigen::VectorXd dT;       // T - t_ref
};
std::optional<TemperatureSpan> temperatureSpan(const TermBuildContext& ctx) {
  const Eigen::VectorXd& T = ctx.in.tested_temperature_degC;
  if (!(T.size() == ctx.n && T.allFinite() &&
        T.maxCoeff() - T.minCoeff() >= ctx.opt.min_temperature_span_degC))
    return std::nullopt;
  TemperatureSpan span;
  span.t_ref_degC = T.mean();
  span.dT = T.array() - span.t_ref_degC;
  return span;
}

}  // namespace

// Against the simulation's temperature, when it carries one, the model is per_degC (T - T_sim):
// the reference temperature is the one behind the simulation's bias (its mean, when it varies).
void temperatureBias(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                     std::vector<CandidateTerm>* out) {
  const std::optional<TemperatureSpan> span = temperatureSpan(ctx);
  if (!span) return;
  const Sensor s = sensorOf(scope);
  const Eigen::VectorXd& T = ctx.in.tested_temperature_degC;
  const Eigen::VectorXd& Ts = ctx.in.simulated_temperature_degC;
  const bool sim_temp = Ts.size() == ctx.n && Ts.allFinite();
  const Eigen::VectorXd dT_bias = sim_temp ? (T - Ts).eval() : span->dT;
  CandidateTerm t(spec, scope);
  t.t_ref_degC = sim_temp ? Ts.mean() : span->t_ref_degC;
  t.mean_is_physical = sim_temp;
  t.explanation = std::string("the ") + sensorName(s) + " bias follows the sensor temperature";
  if (sim_temp)
    t.explanation +=
        " (regressed on the tested minus the simulation's temperature; t_ref_degC "
        "is the simulation's, so the bias at the field's temperature differs "
        "from the simulation's by per_degC (T - t_ref_degC), grafted in full)";
  for (int a = 0; a < 3; ++a) t.columns.push_back(singleChannel(firstChannel(s) + a, dT_bias));
  out->push_back(std::move(t));
}

void temperatureScale(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                      std::vector<CandidateTerm>* out) {
  const std::optional<TemperatureSpan> span = temperatureSpan(ctx);
  if (!span) return;
  const Sensor s = sensorOf(scope);
  const Eigen::MatrixX3d& u = ctx.triad[s].u;
  CandidateTerm t(spec, scope);
  t.t_ref_degC = span->t_ref_degC;
  t.explanation = std::string("the ") + sensorName(s) + " gain follows the sensor temperature";
  for (int a = 0; a < 3; ++a)
    t.columns.push_back(singleChannel(firstChannel(s) + a, span->dT.cwiseProduct(u.col(a))));
  out->push_back(std::move(t));
}

// One term per vibration level the sensor rectifies: the angular-rate level is offered to the
// gyro only (a gyro rectifies its own rate vibration); both sensors rectify linear vibration.
void vibrationRectification(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                            std::vector<CandidateTerm>* out) {
  const Sensor s = sensorOf(scope);
  const std::array<std::pair<TermVariant, const Eigen::VectorXd*>, 2> vib = {
      std::make_pair(TermVariant::specific_force_hp_sq, &ctx.in.vibration_f_hp_sq),
      std::make_pair(TermVariant::angular_rate_hp_sq, &ctx.in.vibration_w_hp_sq)};
  for (int v = 0; v < 2; ++v) {
    if (vib[v].second->size() != ctx.n) continue;
    if (v == 1 && s == Sensor::accel) continue;
    CandidateTerm t(spec, scope, vib[v].first);
    if (s == Sensor::gyro) t.excludes = {TermKey{&spec, scope, vib[1 - v].first}};
    t.explanation = std::string("vibration is rectified into a ") + sensorName(s) +
                    " bias proportional to the " + (v == 0 ? "specific-force" : "angular-rate") +
                    " vibration power";
    // A gain that differs by sign rectifies the rate vibration too; the part inside a sample
    // (vibration near the Nyquist frequency) is not in scale_asymmetry's bin-averaged |x|
    // (random_31_01 at 100 Hz named this term; at 400 Hz the asymmetry, docs/mismatch.md).
    if (v == 1)
      t.explanation +=
          " (a gyro scale_asymmetry rectifies rate vibration the samples do not "
          "resolve in the same way)";
    for (int a = 0; a < 3; ++a)
      t.columns.push_back(singleChannel(firstChannel(s) + a, *vib[v].second));
    out->push_back(std::move(t));
  }
}

}  // namespace graftnav::term_builders
