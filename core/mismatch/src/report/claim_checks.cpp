#include "graftnav/mismatch/claim_checks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "graftnav/mismatch/term_effect.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {
namespace {

constexpr double kAbsorbingMinCorrelation = 0.3;  // below: "a signal outside the library"

// The key of the fitted term an effect came from.
TermKey termKeyOf(const Effect& e, const std::vector<CandidateTerm>& terms,
                  const SelectionResult& sel) {
  for (const TermFit& tf : sel.selected) {
    const CandidateTerm& t = terms[tf.term];
    if (t.spec == e.spec && t.sensor == e.sensor) return t.key();
  }
  return TermKey{e.spec, e.sensor};
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
      !im.absorbing
          ? fmt::format(
                "a signal outside the candidate terms (its columns correlate at most {:.2f} "
                "with another fitted term)",
                most.canonical)
          : fmt::format("{} (canonical correlation {:.3f})", im.absorbing->text(), im.correlation));
  return im;
}

// Step 3: the combined effect, fitted as E per sensor beside the other fitted terms.
Effect combinedEffect(const ClaimCheckInputs& in, const DiagnoseOptions& opt,
                      const std::vector<TermKey>& members, const SeparationNeed& need) {
  std::vector<CandidateTerm> terms = *in.terms;
  terms.push_back(linearResponseTerm(*in.reference));
  const int t_lin = static_cast<int>(terms.size()) - 1;
  std::vector<int> model = {t_lin};
  for (const TermFit& tf : in.selection->selected) {
    const CandidateTerm& t = terms[tf.term];
    bool needs_member = isLinearResponseTerm(t.kind()) || t.part_of.has_value();
    for (const TermKey& req : t.requires_terms)
      for (const CandidateTerm& u : *in.terms)
        if (u.key() == req && isLinearResponseTerm(u.kind())) needs_member = true;
    if (!needs_member && !t.fixed()) model.push_back(tf.term);
  }
  const SelectionResult fit = fitTerms(*in.residual, terms, model, opt.selection);
  Effect e(*terms[t_lin].spec, terms[t_lin].sensor);
  for (const TermFit& tf : fit.selected)
    if (tf.term == t_lin) e = effectFromTerm(terms[t_lin], tf, in.reference->size());
  std::string names;
  for (const TermKey& m : members) names += (names.empty() ? "" : ", ") + m.text();
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
  if (e.spec == nullptr) return worst;
  for (const ParameterSpec& spec : e.spec->parameters) {
    double PlausibleRanges::*const field = boundOf(spec, e.sensor);
    if (field == nullptr) continue;
    const double limit = r.*field;
    for (const EffectParameter& p : e.parameters) {
      if (p.key != spec.key) continue;
      for (std::size_t i = 0; i < p.values.size(); ++i) {
        if (spec.diagonal_only && i % 4 != 0) continue;  // 3x3 row-major: 0, 4, 8
        const double v = std::abs(p.values[i]);
        if (v > limit && (!worst || v / limit > worst->value / worst->bound))
          worst = RangeExcess{p.key, v, limit};
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
          c.term_a.text(), c.term_b.text(), c.canonical,
          100.0 * (1.0 - c.canonical * c.canonical)));
  // Step 3 first: the members are replaced before the range check sees them.
  std::vector<TermKey> members;
  for (const Effect& e : out->effects)
    if (isLinearResponseTerm(e.kind())) members.push_back(termKeyOf(e, *in.terms, *in.selection));
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
                         [](const Effect& e) { return isLinearResponseTerm(e.kind()); }),
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
    if (e.kind() == TermKind::mounting_scale_nonorthogonality) {
      for (const TermKey& m : members) {
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
