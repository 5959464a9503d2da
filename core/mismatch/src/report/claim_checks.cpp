#include "graftnav/mismatch/claim_checks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

namespace graftnav {
namespace {

constexpr double kAbsorbingMinCorrelation = 0.3;  // below: "a signal outside the library"

struct Bound {
  const char* parameter;
  double limit;
  bool diagonal_only;  // a 3x3 matrix of which only the diagonal is bounded
};

std::vector<Bound> boundsOf(const Effect& e, const PlausibleRanges& r) {
  const bool gyro = e.sensor == "gyro";
  if (e.name == "scale_factor") return {{"k", gyro ? r.gyro_scale_max : r.accel_scale_max, false}};
  if (e.name == "non_orthogonality")
    return {
        {"N", gyro ? r.gyro_nonorthogonality_max_rad : r.accel_nonorthogonality_max_rad, false}};
  if (e.name == "scale_asymmetry") {
    const double b = gyro ? r.gyro_scale_asymmetry_max : r.accel_scale_asymmetry_max;
    return {{"k_pos", b, false}, {"k_neg", b, false}};
  }
  if (e.name == "scale_nonlinearity")
    return {
        {"k2",
         gyro ? r.gyro_scale_nonlinearity_max_per_rad_s : r.accel_scale_nonlinearity_max_per_m_s2,
         false}};
  if (e.name == "g_sensitivity") return {{"G", r.g_sensitivity_max_rad_s_per_m_s2, false}};
  if (e.name == "mounting_scale_nonorthogonality")
    return {{"E_gyro", r.gyro_scale_max, true}, {"E_accel", r.accel_scale_max, true}};
  return {};
}

// The key of the fitted term an effect came from (name:sensor[:regressor]).
std::string termKeyOf(const Effect& e, const std::vector<CandidateTerm>& terms,
                      const SelectionResult& sel) {
  for (const TermFit& tf : sel.selected) {
    const CandidateTerm& t = terms[tf.term];
    if (t.name == e.name && t.sensor == e.sensor) return t.key();
  }
  return e.name + ":" + e.sensor;
}

ImplausibleEffect implausibleOf(const Effect& e, const RangeExcess& x, const PlausibleRanges& r,
                                const TermCorrelation& most) {
  ImplausibleEffect im;
  im.effect = e;
  im.parameter = x.parameter;
  im.value = x.value;
  im.bound = x.bound;
  im.sensor_class = r.sensor_class;
  if (most.canonical >= kAbsorbingMinCorrelation) {
    im.absorbing = most.term_b;
    im.correlation = most.canonical;
  }
  im.reason = fmt::format(
      "implausible for this sensor class ({}): |{}| up to {:.3g} against a bound of {:.3g} ({}); "
      "probably absorbing {}",
      r.sensor_class, x.parameter, x.value, x.bound, r.source,
      im.absorbing.empty()
          ? fmt::format(
                "a signal outside the candidate terms (its columns correlate at most {:.2f} "
                "with another fitted term)",
                most.canonical)
          : fmt::format("{} (canonical correlation {:.3f})", im.absorbing, im.correlation));
  return im;
}

// Step 3: the combined effect, fitted as E per sensor beside the other fitted terms.
Effect combinedEffect(const ClaimCheckInputs& in, const DiagnoseOptions& opt,
                      const std::vector<std::string>& members, const SeparationNeed& need) {
  std::vector<CandidateTerm> terms = *in.terms;
  terms.push_back(linearResponseTerm(*in.reference));
  const int t_lin = static_cast<int>(terms.size()) - 1;
  std::vector<int> model = {t_lin};
  for (const TermFit& tf : in.selection->selected) {
    const CandidateTerm& t = terms[tf.term];
    bool needs_member = isLinearResponseTerm(t.name) || !t.part_of.empty();
    for (const std::string& req : t.requires_terms)
      for (const CandidateTerm& u : *in.terms)
        if (u.key() == req && isLinearResponseTerm(u.name)) needs_member = true;
    if (!needs_member && !t.fixed) model.push_back(tf.term);
  }
  const SelectionResult fit = fitTerms(*in.residual, terms, model, opt.selection);
  Effect e;
  e.name = "mounting_scale_nonorthogonality";
  e.sensor = "both";
  for (const TermFit& tf : fit.selected) {
    if (tf.term != t_lin) continue;
    e.delta_bic = tf.delta_bic;
    e.cv_gain = tf.cv_gain;
    for (int s = 0; s < 2; ++s) {
      EffectParameter p;
      p.key = s == 0 ? "E_gyro" : "E_accel";
      for (int k = 0; k < 9; ++k) {
        p.values.push_back(tf.theta(s * 9 + k));
        p.sigma.push_back(tf.sigma(s * 9 + k));
      }
      e.parameters.push_back(p);
    }
  }
  std::string names;
  for (const std::string& m : members) names += (names.empty() ? "" : ", ") + m;
  e.explanation = fmt::format(
      "one linear response per sensor, r_s = E_s x_s with E_s = diag(k_s) + N_s - [phi x]: the "
      "selection fitted {} separately, but this record cannot split them: without a lab "
      "calibration nothing pins N and k, and on this drive the gyros see almost only yaw rate, "
      "so a non-orthogonality N_xz, N_yz and a rotation phi_y, -phi_x are one number each (and "
      "the accelerometers' f_z ~ -g column is one with the bias); {}",
      names, need.text());
  return e;
}

}  // namespace

std::optional<RangeExcess> outsidePlausibleRange(const Effect& e, const PlausibleRanges& r) {
  std::optional<RangeExcess> worst;
  for (const Bound& b : boundsOf(e, r)) {
    for (const EffectParameter& p : e.parameters) {
      if (p.key != b.parameter) continue;
      for (std::size_t i = 0; i < p.values.size(); ++i) {
        if (b.diagonal_only && i % 4 != 0) continue;  // 3x3 row-major: 0, 4, 8
        const double v = std::abs(p.values[i]);
        if (v > b.limit && (!worst || v / b.limit > worst->value / worst->bound))
          worst = RangeExcess{p.key, v, b.limit};
      }
    }
  }
  return worst;
}

void checkClaims(const ClaimCheckInputs& in, const DiagnoseOptions& opt, DiagnosisResult* out) {
  if (!in.terms || !in.selection || !in.reference || !in.residual || !in.masked)
    throw std::invalid_argument("checkClaims: an input is missing");
  out->term_correlations = termCorrelations(*in.terms, *in.selection, *in.masked);
  out->plausible_ranges = in.ranges;
  for (const TermCorrelation& c : out->term_correlations)
    if (c.canonical > opt.max_claim_correlation)
      out->notes.push_back(fmt::format(
          "{} and {} are fitted from columns with a canonical correlation of {:.3f}: their split "
          "rests on {:.1f} % of their signal",
          c.term_a, c.term_b, c.canonical, 100.0 * (1.0 - c.canonical * c.canonical)));
  // Step 3 first: the members are replaced before the range check sees them.
  std::vector<std::string> members;
  for (const Effect& e : out->effects)
    if (isLinearResponseTerm(e.name)) members.push_back(termKeyOf(e, *in.terms, *in.selection));
  if (!members.empty() && !in.lab_calibrated) {
    const double bound =
        in.ranges ? std::min(in.ranges->gyro_nonorthogonality_max_rad,
                             in.ranges->accel_nonorthogonality_max_rad)
                  : plausibleRangesForClass("consumer_mems").gyro_nonorthogonality_max_rad;
    SeparationNeed need =
        separationNeed(*in.reference, *in.selection, in.bin_s, bound, opt.linear_response);
    // The excitation may suffice on average and still leave two members one signal: a column
    // that correlates rho with another member keeps 1 - rho^2 of its information.
    double rho_max = 0.0;
    for (const TermCorrelation& c : out->term_correlations)
      if (std::find(members.begin(), members.end(), c.term_a) != members.end() &&
          std::find(members.begin(), members.end(), c.term_b) != members.end())
        rho_max = std::max(rho_max, c.canonical);
    need.shrinkPresent(1.0 - rho_max * rho_max);
    if (!need.separable) {
      out->separation = need;
      out->effects.erase(
          std::remove_if(out->effects.begin(), out->effects.end(),
                         [](const Effect& e) { return isLinearResponseTerm(e.name); }),
          out->effects.end());
      out->effects.push_back(combinedEffect(in, opt, members, need));
    }
  }
  if (!in.ranges) return;
  std::vector<Effect> kept;
  for (const Effect& e : out->effects) {
    const std::optional<RangeExcess> x = outsidePlausibleRange(e, *in.ranges);
    if (!x) {
      kept.push_back(e);
      continue;
    }
    TermCorrelation most;
    if (e.name == "mounting_scale_nonorthogonality") {
      for (const std::string& m : members) {
        const TermCorrelation c = mostCorrelatedWith(out->term_correlations, m);
        if (c.canonical > most.canonical &&
            std::find(members.begin(), members.end(), c.term_b) == members.end())
          most = c;
      }
    } else {
      most = mostCorrelatedWith(out->term_correlations, termKeyOf(e, *in.terms, *in.selection));
    }
    out->implausible.push_back(implausibleOf(e, *x, *in.ranges, most));
  }
  out->effects = kept;
}

}  // namespace graftnav
