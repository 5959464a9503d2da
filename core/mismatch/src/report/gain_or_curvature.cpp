#include "graftnav/mismatch/gain_or_curvature.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {
namespace {

// chi2 of two estimates of one parameter, and their inverse-variance mean and its sigma.
struct Combined {
  double chi2, value, sigma;
};
Combined combine(double a, double sa, double b, double sb) {
  const double va = sa * sa, vb = sb * sb;
  const double info = 1.0 / va + 1.0 / vb;
  return {(a - b) * (a - b) / (va + vb), (a / va + b / vb) / info, std::sqrt(1.0 / info)};
}

constexpr double kFitsChi2 = 9.0;  // a one-parameter hypothesis fits both observations (3 sigma)

}  // namespace

OneSignedSlope weighOneSignedSlope(const OneSignedSlopeInputs& in) {
  for (double v :
       {in.k, in.k_sigma, in.x_mean, in.c2_lab, in.c2_lab_sigma, in.c2_simulated, in.slope_per_sq})
    if (!std::isfinite(v)) throw std::invalid_argument("weighOneSignedSlope: non-finite input");
  if (!(in.k_sigma > 0.0) || !(in.c2_lab_sigma > 0.0))
    throw std::invalid_argument("weighOneSignedSlope: sigmas must be > 0");
  if (in.x_mean == 0.0) throw std::invalid_argument("weighOneSignedSlope: x_mean must be nonzero");
  OneSignedSlope w;
  const double z1 = in.k + 2.0 * in.c2_simulated * in.x_mean, s1 = in.k_sigma;
  const double z2 = in.c2_lab, s2 = in.c2_lab_sigma;
  w.chi2_gain = z2 * z2 / (s2 * s2);
  const double Bk = 2.0 * in.x_mean - in.slope_per_sq;  // the slope per unit k2 the lab missed
  if (Bk == 0.0) throw std::invalid_argument("weighOneSignedSlope: the curvature has no slope");
  w.k2_field = z1 / Bk;
  w.k2_field_sigma = s1 / std::abs(Bk);
  const Combined curv = combine(z2, s2, w.k2_field, w.k2_field_sigma);
  w.chi2_curvature = curv.chi2;
  w.k2 = curv.value;
  w.k2_sigma = curv.sigma;
  std::vector<std::pair<double, SlopeCause>> ranked = {{w.chi2_gain, SlopeCause::kGain},
                                                       {w.chi2_curvature, SlopeCause::kCurvature}};
  if (std::isfinite(in.slope_per_abs) && std::isfinite(in.c2_per_abs) && in.c2_per_abs != 0.0) {
    const double Ad = (in.x_mean > 0.0 ? 1.0 : -1.0) - in.slope_per_abs;  // slope per unit d
    if (Ad != 0.0) {
      const Combined asym =
          combine(z1 / Ad, s1 / std::abs(Ad), z2 / in.c2_per_abs, s2 / std::abs(in.c2_per_abs));
      w.chi2_asymmetry = asym.chi2;
      ranked.push_back({w.chi2_asymmetry, SlopeCause::kAsymmetry});
      w.d = asym.value;  // with no curvature beside it, unless the two-parameter fit exists
      w.d_sigma = asym.sigma;
      w.k2_beside_d = 0.0;
      w.k2_beside_d_sigma = 0.0;
      // Two parameters, d and k2, from the two observations (exact), unless d's column is
      // proportional to k2's (D = 0: the curvature and the asymmetry are then one column for
      // both lab and field, and their chi2 equal).
      const double D = Ad - Bk * in.c2_per_abs;
      if (std::abs(D) > 1e-6 * (std::abs(Ad) + std::abs(Bk * in.c2_per_abs))) {
        w.d = (z1 - Bk * z2) / D;
        w.d_sigma = std::sqrt(s1 * s1 + Bk * Bk * s2 * s2) / std::abs(D);
        w.k2_beside_d = z2 - w.d * in.c2_per_abs;
        const double a = 1.0 + in.c2_per_abs * Bk / D, b = in.c2_per_abs / D;
        w.k2_beside_d_sigma = std::sqrt(a * a * s2 * s2 + b * b * s1 * s1);
        w.d_with_curvature = true;
      }
    }
  }
  std::sort(ranked.begin(), ranked.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  if (ranked[0].first > kFitsChi2) return w;  // none fits: unsettled, margin 0
  w.best = ranked[0].second;
  w.runner_up = ranked[1].second;
  w.margin = ranked[1].first - ranked[0].first;
  return w;
}

TermKind slopeCauseKind(SlopeCause c) {
  switch (c) {
    case SlopeCause::kGain:
      return TermKind::scale_factor;
    case SlopeCause::kCurvature:
      return TermKind::scale_nonlinearity;
    case SlopeCause::kAsymmetry:
      return TermKind::scale_asymmetry;
    case SlopeCause::kUnsettled:
      break;
  }
  throw std::invalid_argument("slopeCauseKind: an unsettled slope names no term");
}

std::string slopeCauseName(SlopeCause c) {
  return c == SlopeCause::kUnsettled ? "unsettled" : termName(slopeCauseKind(c));
}

bool oneSignedInput(double mean, double sd, double min_ratio) {
  return std::isfinite(mean) && std::isfinite(sd) && std::abs(mean) >= min_ratio * sd &&
         mean != 0.0;
}

namespace {

// `e` as another term, with its sensor and evidence; parameters and explanation left empty.
Effect renamed(const Effect& e, TermKind kind) {
  Effect c(termSpec(kind), e.sensor);
  c.delta_bic = e.delta_bic;
  c.cv_gain = e.cv_gain;
  c.evidence_method = e.evidence_method;
  return c;
}

// The scale_factor effect `e` renamed scale_nonlinearity: the sensor's k2 with axis a from the
// weighing (lab and field combined), the other axes the lab's.
Effect curvatureEffect(const Effect& e, int a, const OneSignedSlope& w, double c2_simulated,
                       const LabQuadratic& lab, const std::string& weighed) {
  Effect c = renamed(e, TermKind::scale_nonlinearity);
  EffectParameter k2, missing;
  k2.key = "k2";
  missing.key = "k2_missing";
  for (int b = 0; b < 3; ++b) {
    double v = 0.0, sd = NAN;
    if (b == a) {
      v = w.k2;
      sd = w.k2_sigma;
    } else if (lab.c2(b) != 0.0) {
      v = lab.c2(b);
      sd = lab.c2_sigma(b);
    } else if (std::isfinite(lab.c2_tested(b))) {
      v = lab.c2_tested(b);
      sd = lab.c2_tested_sigma(b);
    }
    k2.values.push_back(v);
    k2.sigma.push_back(sd);
    missing.values.push_back(b == a ? w.k2 - c2_simulated : 0.0);
    missing.sigma.push_back(b == a ? w.k2_sigma : NAN);
  }
  c.parameters = {k2, missing};
  c.explanation = fmt::format(
      "the {} input-output line bends: output = input + k2 input^2; {}. k2: {} the lab's and "
      "the field's estimates combined, the other axes the lab's (its quadratic where its test "
      "kept one, else its degree-2 estimate); k2_missing: what SG#2 lacks. SG#3 models it as "
      "the field's slope at the mean input (the same column there)",
      sensorNoun(sensorOf(e.sensor)), weighed, "xyz"[a]);
  return c;
}

// The scale_factor effect `e` renamed scale_asymmetry: gains per sign +-d about the sensor's
// mean gain on axis a (no gain change between lab and field there), the other axes undetermined.
Effect asymmetryEffect(const Effect& e, int a, const OneSignedSlope& w,
                       const std::string& weighed) {
  Effect c = renamed(e, TermKind::scale_asymmetry);
  EffectParameter kp, kn;
  kp.key = "k_pos";
  kn.key = "k_neg";
  for (int b = 0; b < 3; ++b) {
    kp.values.push_back(b == a ? w.d : 0.0);
    kn.values.push_back(b == a ? -w.d : 0.0);
    kp.sigma.push_back(b == a ? w.d_sigma : NAN);
    kn.sigma.push_back(b == a ? w.d_sigma : NAN);
  }
  c.parameters = {kp, kn};
  c.explanation = fmt::format(
      "the {} gain differs for positive and negative inputs; {}. k_pos / k_neg: the gains per "
      "sign about the sensor's mean gain (+-d, d = {:.3g} +- {:.2g}, {}); the other axes are "
      "not determined by this evidence. The lab's quadratic on {} in SG#2 is mostly this "
      "asymmetry as its poses saw it; SG#3 models the field's slope at the mean input (the same "
      "column there)",
      sensorNoun(sensorOf(e.sensor)), weighed, w.d, w.d_sigma,
      w.d_with_curvature
          ? fmt::format("estimated with the sensor's own curvature on {} left free: k2 = {:.3g} "
                        "+- {:.2g}",
                        "xyz"[a], w.k2_beside_d, w.k2_beside_d_sigma)
          : std::string("its column and the curvature's are one here: estimated without one"),
      "xyz"[a]);
  return c;
}

// How the field's slope on `axis` was weighed against the lab's degree-2 coefficient, for the
// effect's explanation.
std::string describeWeighing(int a, double x_mean, double x_sd, const OneSignedSlopeInputs& wi,
                             bool kept_quadratic, double lab_c2, const OneSignedSlope& w) {
  const char axis = "xyz"[a];
  std::string weighed = fmt::format(
      "on {} the input keeps one sign (mean {:.3g}, sd {:.2g}), where a gain, a curvature and "
      "an asymmetry are one column: the field's slope k_{} = {:.3g} +- {:.2g} against SG#2 "
      "(its gain uncertainty included; SG#2 grafts {}) is weighed with the lab's degree-2 "
      "coefficient there, {:.3g} +- {:.2g} "
      "({}); chi-square of one-parameter explanations: a gain change between lab and field "
      "{:.1f}, a curvature {:.1f} (k2 = {:.3g} +- {:.2g})",
      axis, x_mean, x_sd, axis, wi.k, wi.k_sigma,
      kept_quadratic ? fmt::format("the lab's quadratic, c2 = {:.3g}", lab_c2)
                     : std::string("the lab's line"),
      wi.c2_lab, wi.c2_lab_sigma,
      kept_quadratic ? "kept by its degree test; its -g/0/+g poses see an asymmetry d |x| as "
                       "a quadratic"
                     : "not significant at its degree test",
      w.chi2_gain, w.chi2_curvature, w.k2, w.k2_sigma);
  if (std::isfinite(w.chi2_asymmetry))
    weighed += fmt::format(
        ", an asymmetry the lab folded into its quadratic {:.1f} (d = {:.3g} "
        "+- {:.2g} with a curvature {:.3g} +- {:.2g} beside it)",
        w.chi2_asymmetry, w.d, w.d_sigma, w.k2_beside_d, w.k2_beside_d_sigma);
  return weighed;
}

// Settles one axis's one-signed slope: a gain (kept), a curvature or an asymmetry (replacing the
// gain), or not settled (listed as ambiguous).
void settleOneSignedSlope(Effect e, int a, const OneSignedSlope& w, const OneSignedSlopeInputs& wi,
                          const LabQuadratic& lab, double min_margin, std::string weighed,
                          DiagnosisResult* out, std::vector<Effect>* kept,
                          std::vector<Sensor>* lab_quadratic_not_listed) {
  if (w.best == SlopeCause::kUnsettled) {
    // No single cause fits: a gain change beside the lab's curvature and an asymmetry beside a
    // curvature are exact two-parameter fits alike.
    e.explanation += "; " + weighed + ": none fits alone (chi-square > 9); " +
                     (std::isfinite(w.chi2_asymmetry)
                          ? "a gain change beside a curvature and an asymmetry beside a "
                            "curvature fit alike: not settled"
                          : "a gain change beside a curvature fits, and the lab's responses "
                            "needed to weigh an asymmetry are missing: not settled");
    const TermKind alternative =
        std::isfinite(w.chi2_asymmetry) ? TermKind::scale_asymmetry : TermKind::scale_nonlinearity;
    out->ambiguous.push_back({std::move(e), &termSpec(alternative), 0.0});
    return;
  }
  if (w.margin < min_margin) {
    weighed += fmt::format(": {} leads {} by {:.1f}, not settled", slopeCauseName(w.best),
                           slopeCauseName(w.runner_up), w.margin);
    if (w.best == SlopeCause::kGain || w.runner_up == SlopeCause::kGain) {
      // The gain is one of the two: listed as fitted, the other cause the alternative, the
      // margin the gain's evidence over it (negative when the other fits better).
      const bool gain_best = w.best == SlopeCause::kGain;
      e.explanation += "; " + weighed;
      out->ambiguous.push_back({std::move(e),
                                &termSpec(slopeCauseKind(gain_best ? w.runner_up : w.best)),
                                gain_best ? w.margin : -w.margin});
    } else {
      // A curvature against an asymmetry, the gain out of it: listed under the better.
      out->ambiguous.push_back({w.best == SlopeCause::kCurvature
                                    ? curvatureEffect(e, a, w, wi.c2_simulated, lab, weighed)
                                    : asymmetryEffect(e, a, w, weighed),
                                &termSpec(slopeCauseKind(w.runner_up)), w.margin});
    }
    return;
  }
  weighed += fmt::format(": {} leads by {:.1f}", slopeCauseName(w.best), w.margin);
  if (w.best == SlopeCause::kGain) {
    e.explanation += "; " + weighed + ": a gain";
    kept->push_back(std::move(e));
    return;
  }
  if (w.best == SlopeCause::kAsymmetry) {
    kept->push_back(asymmetryEffect(e, a, w, weighed));
    return;
  }
  kept->push_back(curvatureEffect(e, a, w, wi.c2_simulated, lab, weighed));
  const Sensor sensor = sensorOf(e.sensor);
  if (std::find(lab_quadratic_not_listed->begin(), lab_quadratic_not_listed->end(), sensor) ==
      lab_quadratic_not_listed->end())
    lab_quadratic_not_listed->push_back(sensor);
}

}  // namespace

void nameOneSignedGains(const DiagnosisInputs& in, const PerSensor<Eigen::Vector3d>& input_mean,
                        const PerSensor<Eigen::Vector3d>& input_sd, double min_margin,
                        DiagnosisResult* out, std::vector<Sensor>* lab_quadratic_not_listed) {
  // Sensors whose curvature the field named itself, read before the loop moves effects out.
  // So are those whose asymmetry it named: a second one would count the fold twice.
  std::vector<SensorScope> even_claimed;
  for (const Effect& e : out->effects)
    if (e.kind() == TermKind::scale_nonlinearity || e.kind() == TermKind::scale_asymmetry)
      even_claimed.push_back(e.sensor);
  std::vector<Effect> kept;
  for (Effect& e : out->effects) {
    // A curvature or an asymmetry the field named itself is already claimed: the gain stays.
    if (e.kind() != TermKind::scale_factor || !isSingleSensor(e.sensor)) {
      kept.push_back(std::move(e));
      continue;
    }
    const Sensor s = sensorOf(e.sensor);
    const std::optional<LabQuadratic>& lab = in.priors[s].lab_quadratic;
    if (!lab || e.parameters.empty() ||
        std::find(even_claimed.begin(), even_claimed.end(), e.sensor) != even_claimed.end()) {
      kept.push_back(std::move(e));
      continue;
    }
    const EffectParameter& k = e.parameters[0];
    std::vector<int> significant;
    for (int b = 0; b < 3; ++b)
      if (std::isfinite(k.sigma[b]) && std::abs(k.values[b]) > 3.0 * k.sigma[b])
        significant.push_back(b);
    const int a = significant.size() == 1 ? significant[0] : -1;
    // The lab's degree-2 coefficient on the axis: its kept quadratic (which SG#2 grafts; weighed
    // only with the fit's responses, without which the fold cannot be told), else the estimate
    // its test dropped.
    const bool kept_quadratic = a >= 0 && lab->c2(a) != 0.0;
    const double c2_lab = a < 0 ? NAN : kept_quadratic ? lab->c2(a) : lab->c2_tested(a);
    const double c2_lab_sigma = a < 0            ? NAN
                                : kept_quadratic ? lab->c2_sigma(a)
                                                 : lab->c2_tested_sigma(a);
    if (a < 0 || !std::isfinite(c2_lab) || !(c2_lab_sigma > 0.0) ||
        (kept_quadratic &&
         !(std::isfinite(lab->slope_per_abs(a)) && std::isfinite(lab->c2_tested_per_abs(a)))) ||
        !oneSignedInput(input_mean[s](a), input_sd[s](a))) {
      kept.push_back(std::move(e));
      continue;
    }
    // The field slope is measured against SG#2's gain, the lab's estimate on the reference
    // signal: their uncertainties are the slope's too (as in the scale factor's gate).
    const std::optional<Eigen::Matrix3d>& lab_M_sigma = in.priors[s].lab_M_sigma;
    const std::optional<double>& ref_scale_sigma = in.priors[s].reference_scale_sigma;
    OneSignedSlopeInputs wi;
    wi.k = k.values[a];
    wi.k_sigma =
        std::sqrt(k.sigma[a] * k.sigma[a] + std::pow(lab_M_sigma ? (*lab_M_sigma)(a, a) : 0.0, 2) +
                  std::pow(ref_scale_sigma.value_or(0.0), 2));
    wi.x_mean = input_mean[s](a);
    wi.c2_lab = c2_lab;
    wi.c2_lab_sigma = c2_lab_sigma;
    wi.c2_simulated = kept_quadratic ? lab->c2(a) : 0.0;
    wi.slope_per_sq =
        kept_quadratic || !std::isfinite(lab->slope_per_sq(a)) ? 0.0 : lab->slope_per_sq(a);
    wi.slope_per_abs = lab->slope_per_abs(a);
    wi.c2_per_abs = lab->c2_tested_per_abs(a);
    const OneSignedSlope w = weighOneSignedSlope(wi);
    settleOneSignedSlope(std::move(e), a, w, wi, *lab, min_margin,
                         describeWeighing(a, input_mean[s](a), input_sd[s](a), wi, kept_quadratic,
                                          kept_quadratic ? lab->c2(a) : 0.0, w),
                         out, &kept, lab_quadratic_not_listed);
  }
  out->effects = std::move(kept);
}

}  // namespace graftnav
