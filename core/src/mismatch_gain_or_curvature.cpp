#include "graftnav/core/mismatch/gain_or_curvature.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/core/mismatch/diagnosis.h"

namespace graftnav {

GainOrCurvature weighGainAgainstCurvature(const GainOrCurvatureInputs& in) {
  for (double v : {in.k, in.k_sigma, in.x_mean, in.c2_lab, in.c2_lab_sigma})
    if (!std::isfinite(v)) throw std::invalid_argument("weighGainAgainstCurvature: non-finite input");
  if (!(in.k_sigma > 0.0) || !(in.c2_lab_sigma > 0.0))
    throw std::invalid_argument("weighGainAgainstCurvature: sigmas must be > 0");
  if (in.x_mean == 0.0)
    throw std::invalid_argument("weighGainAgainstCurvature: x_mean must be nonzero");
  GainOrCurvature w;
  w.k2_field = in.k / (2.0 * in.x_mean);
  w.k2_field_sigma = in.k_sigma / (2.0 * std::abs(in.x_mean));
  const double lab_var = in.c2_lab_sigma * in.c2_lab_sigma;
  const double field_var = w.k2_field_sigma * w.k2_field_sigma;
  const double info = 1.0 / lab_var + 1.0 / field_var;
  w.k2 = (in.c2_lab / lab_var + w.k2_field / field_var) / info;
  w.k2_sigma = std::sqrt(1.0 / info);
  const double chi2_gain = in.c2_lab * in.c2_lab / lab_var;
  const double chi2_curvature = std::pow(in.c2_lab - w.k2_field, 2) / (lab_var + field_var);
  w.margin = chi2_gain - chi2_curvature;
  return w;
}

bool oneSignedInput(double mean, double sd, double min_ratio) {
  return std::isfinite(mean) && std::isfinite(sd) && std::abs(mean) >= min_ratio * sd &&
         mean != 0.0;
}

void nameOneSignedGains(const DiagnosisInputs& in, const std::array<Eigen::Vector3d, 2>& input_mean,
                        const std::array<Eigen::Vector3d, 2>& input_sd, double min_margin,
                        DiagnosisResult* out, std::vector<std::string>* lab_quadratic_not_listed) {
  // Sensors whose curvature the field named itself, read before the loop moves effects out.
  std::vector<std::string> curvature_claimed;
  for (const Effect& e : out->effects)
    if (e.name == "scale_nonlinearity") curvature_claimed.push_back(e.sensor);
  std::vector<Effect> kept;
  for (Effect& e : out->effects) {
    const int s = e.sensor == "gyro" ? 0 : e.sensor == "accel" ? 1 : -1;
    const std::optional<LabQuadratic>& lab =
        s == 0 ? in.lab_gyro_quadratic : in.lab_accel_quadratic;
    // A curvature the field named itself is already claimed: the gain stays a gain.
    if (e.name != "scale_factor" || s < 0 || !lab || e.parameters.empty() ||
        std::find(curvature_claimed.begin(), curvature_claimed.end(), e.sensor) !=
            curvature_claimed.end()) {
      kept.push_back(std::move(e));
      continue;
    }
    const EffectParameter& k = e.parameters[0];
    std::vector<int> significant;
    for (int a = 0; a < 3; ++a)
      if (std::isfinite(k.sigma[a]) && std::abs(k.values[a]) > 3.0 * k.sigma[a])
        significant.push_back(a);
    const int a = significant.size() == 1 ? significant[0] : -1;
    if (a < 0 || lab->c2(a) != 0.0 || !std::isfinite(lab->c2_tested(a)) ||
        !(lab->c2_tested_sigma(a) > 0.0) || !oneSignedInput(input_mean[s](a), input_sd[s](a))) {
      kept.push_back(std::move(e));
      continue;
    }
    const GainOrCurvature w = weighGainAgainstCurvature(
        {k.values[a], k.sigma[a], input_mean[s](a), lab->c2_tested(a), lab->c2_tested_sigma(a)});
    const char axis = "xyz"[a];
    const std::string weighed = fmt::format(
        "on {} the input keeps one sign (mean {:.3g}, sd {:.2g}), where a gain k and a curvature "
        "k2 are one column, k = 2 k2 x_mean: the field's k_{} = {:.3g} +- {:.2g} is k2 = {:.3g} "
        "+- {:.2g}; the lab's line has the slope of its -g/0/+g poses, which a curvature does "
        "not move, and its degree-2 estimate, not significant at its test, is {:.3g} +- {:.2g}; "
        "evidence for the curvature over a gain change between lab and field: {:.1f} (2 ln "
        "likelihood ratio)",
        axis, input_mean[s](a), input_sd[s](a), axis, k.values[a], k.sigma[a], w.k2_field,
        w.k2_field_sigma, lab->c2_tested(a), lab->c2_tested_sigma(a), w.margin);
    if (w.margin <= -min_margin) {
      e.explanation += "; " + weighed + ": a gain";
      kept.push_back(std::move(e));
      continue;
    }
    if (w.margin < min_margin) {
      e.explanation += "; " + weighed + ": not settled";
      out->ambiguous.push_back({std::move(e), "scale_nonlinearity", -w.margin});
      continue;
    }
    Effect c;
    c.name = "scale_nonlinearity";
    c.sensor = e.sensor;
    c.delta_bic = e.delta_bic;
    c.cv_gain = e.cv_gain;
    c.evidence_method = e.evidence_method;
    EffectParameter k2, missing;
    k2.key = "k2";
    missing.key = "k2_missing";
    for (int b = 0; b < 3; ++b) {
      double v = 0.0, sd = NAN;
      if (b == a) {
        v = w.k2;
        sd = w.k2_sigma;
      } else if (lab->c2(b) != 0.0) {
        v = lab->c2(b);
        sd = lab->c2_sigma(b);
      } else if (std::isfinite(lab->c2_tested(b))) {
        v = lab->c2_tested(b);
        sd = lab->c2_tested_sigma(b);
      }
      k2.values.push_back(v);
      k2.sigma.push_back(sd);
      missing.values.push_back(b == a ? w.k2 : 0.0);
      missing.sigma.push_back(b == a ? w.k2_sigma : NAN);
    }
    c.parameters = {k2, missing};
    c.explanation = fmt::format(
        "the {} input-output line bends: output = input + k2 input^2; {}. k2: {} the lab's and "
        "the field's estimates combined, the other axes the lab's (its quadratic where its test "
        "kept one, else its degree-2 estimate); k2_missing: what SG#2 lacks. SG#3 models it as "
        "the field's slope at the mean input (the same column there)",
        e.sensor == "gyro" ? "gyro" : "accelerometer", weighed, axis);
    if (std::find(lab_quadratic_not_listed->begin(), lab_quadratic_not_listed->end(), e.sensor) ==
        lab_quadratic_not_listed->end())
      lab_quadratic_not_listed->push_back(e.sensor);
    kept.push_back(std::move(c));
  }
  out->effects = std::move(kept);
}

}  // namespace graftnav
