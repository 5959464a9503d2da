// The finder's scale-asymmetry gains: a claimed asymmetry is reported as the sensor's own gains
// per sign, fitted on tested minus reference beside the scale factor the simulation lacks.
#include <algorithm>
#include <cmath>
#include <string>

#include "diagnosis_stages.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav::diagnosis_detail {

namespace {

// Scale asymmetry is a sensor property the simulation may partly hold already: SG#2's lab
// fitting polynomial sees an asymmetric gain k_a |x| on the rate table (+-30 and +-90 deg/s)
// and, when cross-validation picks degree 2, fits it as c2 x^2, which in the field covers part
// of k_a; the residual then shows only what SG#2 lacks (17 % of k_pos - k_neg on the concealed
// scale_asymmetry case). The reported k_pos / k_neg are the sensor's gains per sign relative
// to the simulation's linear gain, k = k_missing +- d: d is the sensor's own asymmetry, the
// same model fitted to tested minus reference, y - x, plus that sensor's scale factor and
// non-orthogonality (the lab's terms are in y - x, not in r); k_missing is the scale factor
// the simulation lacks (the companion scale_factor of the residual fit). When k was the
// sensor's whole scale factor of the y - x fit, which holds the tested IMU's
// calibrated gain error (0.1-0.3 % for MEMS): element by element against an injected +-d the
// gains were 3.2-98 sigma off on all 63 gyro asymmetries found on random seeds 15-25 (their
// difference within 3 sigma or 20 %); now within 3 sigma on all.
// The mean of the two gains is the lab's (its +-g poses and turns of both signs see it), so a
// one-sided asymmetry (k_neg = 0) comes back as +-d about the lab's gain: only k_pos - k_neg
// is identifiable. Uncertainties: the fits', and the gain they are measured about: the
// simulation's gain is the lab's estimate (M_sigma on the diagonal) built on the reference
// signal (its stated scale uncertainty), so k_missing holds those errors too, which the scale
// factor's gate allows for (random_22_02, consumer gyro: k_missing z -4.3e-4 +- 1.2e-4 with
// no gain missing made k_neg 4.3 sigma off the injected -d). The part missing from the
// simulation, which SG#3 grafts, is k_pos_missing / k_neg_missing (fit uncertainties).

// The same-sensor terms of the sensor's own fit (-1: not in the library).
struct AsymmetryTerms {
  int asym = -1, nonorth = -1, scale = -1, curv = -1;
};

AsymmetryTerms asymmetryTermsOf(const std::vector<CandidateTerm>& terms, Sensor sensor) {
  AsymmetryTerms at;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    if (terms[t].sensor != scopeOf(sensor)) continue;
    const TermKind kind = terms[t].kind();
    // The plain |x| columns: y - x holds the sensor, not SG#2's quadratic.
    if (kind == TermKind::scale_asymmetry && terms[t].variant == TermVariant::none)
      at.asym = static_cast<int>(t);
    if (kind == TermKind::non_orthogonality && terms[t].variant == TermVariant::none)
      at.nonorth = static_cast<int>(t);
    if (kind == TermKind::scale_factor) at.scale = static_cast<int>(t);
    if (kind == TermKind::scale_nonlinearity) at.curv = static_cast<int>(t);
  }
  return at;
}

// The sensor's own curvature is in y - x too. Where the lab kept a quadratic it measured
// c2 = k2 + d c2_tested_per_abs (its poses fold the asymmetry in), so on that axis the
// asymmetry's column is |x| - c2_tested_per_abs x^2 beside the known part c2 x^2. Without
// it a curvature the lab measured leaked into |x| (random_31_23: d_x 16 % high, k_neg x
// 3.3 sigma off, beside an injected accelerometer curvature SG#2 grafts). Not when a
// scale_nonlinearity of the sensor is claimed (its x^2 column is free in the model). The
// lab's c2 uncertainty is left out of d's sigma (x^2's share of |x|: c2_sigma times a few
// m/s^2 for the accelerometer, small beside the field's).
// Returns the library with that change (empty: unchanged) and adds the known part to `model`.
std::vector<CandidateTerm> withLabCurvatureKnown(const std::vector<CandidateTerm>& terms,
                                                 const AsymmetryTerms& at, Sensor sensor,
                                                 const std::optional<LabQuadratic>& quad,
                                                 std::vector<int>* model) {
  std::vector<CandidateTerm> own_terms;  // a copy of the library only when changed
  const bool curvature_free =
      at.curv >= 0 && std::find(model->begin(), model->end(), at.curv) != model->end();
  if (!(quad && at.asym >= 0 && at.curv >= 0 && !curvature_free &&
        ((quad->c2.array() != 0.0) && quad->c2_tested_per_abs.array().isFinite()).any()))
    return own_terms;
  own_terms = terms;
  CandidateTerm known(termSpec(TermKind::lab_curvature_known), scopeOf(sensor));
  known.explanation = "the lab's quadratic less the asymmetry's fold in it";
  RegressorColumn col;
  for (int a = 0; a < 3; ++a) {
    const int ch = firstChannel(sensor) + a;
    if (quad->c2(a) == 0.0 || !std::isfinite(quad->c2_tested_per_abs(a)) ||
        !own_terms[at.curv].columns[a].actsOn(ch) || !own_terms[at.asym].columns[a].actsOn(ch))
      continue;
    const Eigen::VectorXd& u_sq = own_terms[at.curv].columns[a].channel[ch];
    own_terms[at.asym].columns[a].channel[ch] -= quad->c2_tested_per_abs(a) * u_sq;
    col.channel[ch] = quad->c2(a) * u_sq;
  }
  if (std::any_of(col.channel.begin(), col.channel.end(),
                  [](const Eigen::VectorXd& v) { return v.size() > 0; })) {
    known.columns.push_back(col);
    own_terms.push_back(known);
    model->push_back(static_cast<int>(own_terms.size()) - 1);
  }
  return own_terms;
}

// k = k_missing +- d per axis, with the uncertainty of the lab's and the reference's gain.
void setGainsPerSign(const SensorPriors& prior, const TermFit& fit_asym,
                     const TermFit* scale_missing, const Eigen::Vector3d& mean_input, Effect* e) {
  const std::optional<LabQuadratic>& quad = prior.lab_quadratic;
  EffectParameter kp = e->parameters[0], kn = e->parameters[1];
  const std::optional<Eigen::Matrix3d>& lab_M_sigma = prior.lab_M_sigma;
  const std::optional<double>& ref_scale_sigma = prior.reference_scale_sigma;
  // SG#2's gain at the drive's mean input x_m is c1 + 2 c2 x_m: with a lab quadratic its c2
  // uncertainty is a gain uncertainty there too (as in the gate; ~0 on two-signed axes).
  for (int a = 0; a < 3; ++a) {
    const double d = fit_asym.theta(a);
    const double k = scale_missing ? scale_missing->theta(a) : 0.0;
    const double k_sigma = scale_missing ? scale_missing->sigma(a) : 0.0;
    const double c2_sigma = quad && quad->c2(a) != 0.0 ? quad->c2_sigma(a) : 0.0;
    const double gain_sigma = std::sqrt(std::pow(lab_M_sigma ? (*lab_M_sigma)(a, a) : 0.0, 2) +
                                        std::pow(ref_scale_sigma.value_or(0.0), 2) +
                                        std::pow(2.0 * mean_input(a) * c2_sigma, 2));
    kp.values[a] = k + d;
    kn.values[a] = k - d;
    kp.sigma[a] = kn.sigma[a] =
        std::sqrt(std::pow(fit_asym.sigma(a), 2) + k_sigma * k_sigma + gain_sigma * gain_sigma);
  }
  EffectParameter missing_pos = e->parameters[0], missing_neg = e->parameters[1];
  missing_pos.key = "k_pos_missing";
  missing_neg.key = "k_neg_missing";
  e->parameters = {kp, kn, missing_pos, missing_neg};
  e->explanation +=
      " (k_pos / k_neg: the sensor's gains per sign relative to the "
      "simulation's linear gain, i.e. its own asymmetry +-d fitted on tested "
      "minus reference (beside the curvature its lab measured) plus the scale "
      "factor the simulation lacks; only k_pos - k_neg is "
      "identifiable, their mean is the lab's, and their uncertainty includes "
      "that of the lab's and the reference's gain; *_missing: the part the "
      "simulation lacks)";
}

}  // namespace

void ownAsymmetryGains(const ClaimInputs& c, const Vector6d& ref_input_mean, DiagnosisResult* out) {
  const std::vector<CandidateTerm>& terms = c.ex.terms;
  const SelectionResult& sel = c.ex.sel;
  const int n = c.bins.n();
  std::vector<int> claimed_terms;
  for (const TermFit& tf : sel.selected)
    if (tf.claimed) claimed_terms.push_back(tf.term);
  for (Effect& e : out->effects) {
    if (e.kind() != TermKind::scale_asymmetry) continue;
    const Sensor sensor = sensorOf(e.sensor);
    const AsymmetryTerms at = asymmetryTermsOf(terms, sensor);
    std::vector<int> model;
    for (int t : claimed_terms)  // the alternative replacing SG#2's quadratic: its plain columns
      if (terms[t].variant != TermVariant::replaces_lab_quadratic) model.push_back(t);
    for (int t : {at.asym, at.nonorth, at.scale})
      if (t >= 0 && std::find(model.begin(), model.end(), t) == model.end()) model.push_back(t);
    const std::optional<LabQuadratic>& quad = c.in.priors[sensor].lab_quadratic;
    const std::vector<CandidateTerm> own_terms =
        withLabCurvatureKnown(terms, at, sensor, quad, &model);
    Eigen::MatrixXd y_minus_x(n, kMismatchChannels);
    y_minus_x << c.bins.y.omega_rad_s - c.bins.x.omega_rad_s, c.bins.y.f_m_s2 - c.bins.x.f_m_s2;
    zeroMaskedRows(out->masked_bins, &y_minus_x);
    const SelectionResult own =
        fitTerms(y_minus_x, own_terms.empty() ? terms : own_terms, model, c.opt.selection);
    const TermFit* fit_asym = nullptr;
    for (const TermFit& tf : own.selected)
      if (tf.term == at.asym) fit_asym = &tf;
    const TermFit* scale_missing = nullptr;  // in the model as the asymmetry's companion
    for (const TermFit& tf : sel.selected)
      if (tf.term == at.scale) scale_missing = &tf;
    if (fit_asym)
      setGainsPerSign(c.in.priors[sensor], *fit_asym, scale_missing,
                      ref_input_mean.segment<3>(firstChannel(sensor)), &e);
  }
}

}  // namespace graftnav::diagnosis_detail
