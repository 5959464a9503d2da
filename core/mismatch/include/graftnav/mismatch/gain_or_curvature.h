#pragma once
// Gain, curvature or folded asymmetry: naming a field gain error on an axis whose input keeps
// one sign.
//
// On an axis whose field input stays near a large mean x_m (the accelerometer that carries
// gravity, f_z ~ -g), a gain error, a curvature k2 (output = input + k2 input^2) and a scale
// asymmetry d (output = input + d |input|) are one column to first order: the field measures one
// slope there. The lab tells them apart, or says it cannot: its poses at -g, 0, +g leave the
// line's slope untouched by a curvature (the quadratic is even) while its degree-2 coefficient
// sees k2 directly, and they see an asymmetry as the quadratic d / g x^2 (the lab "folds" it).
// Two cases reach the field as a claimed scale factor on that axis:
//  - the lab's degree test kept a line (the curvature was not significant at its 1 % level,
//    PolynomialFit::c2_tested), so SG#2 grafts no curvature: random_26_05, k_z = 1.2e-3 at
//    6.5 sigma from an injected k2_z = -6.6e-5 per m/s^2, estimated by the lab as
//    -5.1e-5 +- 1.7e-5 and dropped;
//  - the lab kept a quadratic there and SG#2 grafts it, but the quadratic is a folded one-sided
//    asymmetry: at -g the sensor has the gain of its negative side, which SG#2's line-plus-
//    quadratic misses by d (random_23_13: a z asymmetry d = -2.9e-3 claimed as a -3.9e-3 z scale
//    factor).
//
// Observations: z1 = k + 2 c2_sim x_m +- sigma_k (the field's slope less SG#2's lab slope c1,
// k the residual's slope and c2_sim the quadratic SG#2 grafts there, 0 for a line; sigma_k
// includes c1's uncertainty) and z2 = c2_lab +- s (the lab's degree-2 coefficient, kept or only
// tested), taken as independent: exact when the lab kept a line (its slope and the degree-2
// fit's c2 are orthogonal estimates); with a kept quadratic c1 and c2 correlate through the
// poses' asymmetry (zero for poses symmetric about 0, small with one tilted pose). With the
// lab fit's responses (PolynomialFit::slope_per_abs, slope_per_sq, c2_tested_per_abs) the
// sensor's k_g (gain change between lab and field), k2 and d give
//   z1 = k_g + d (sign(x_m) - slope_per_abs) + k2 (2 x_m - slope_per_sq)
//   z2 = k2 + d c2_tested_per_abs.
// Three hypotheses, one free parameter each, their chi-square (2 ln likelihood up to a common
// constant; with one parameter each the Occam factors are alike and left out):
//   gain:       k_g only:  chi2 = (z2 / s)^2
//   curvature:  k2 only:   z1 and z2 both estimate k2
//   asymmetry:  d only:    z1 and z2 both estimate d (weighed only with the lab's responses)
// The best is named when it leads the next by min_margin; otherwise the effect is listed as
// ambiguous. When none fits (best chi2 > 9: the lab's quadratic is real and the field's slope
// is more than its fold), two parameters are needed and a gain change with the lab's curvature
// fits exactly as well as an asymmetry with a curvature beside it: ambiguous, margin 0. A named
// curvature's k2 combines both estimates; a named asymmetry's d is the two-parameter estimate
// (asymmetry plus the sensor's curvature on that axis), which does not assume the lab's
// quadratic is all asymmetry.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"

namespace graftnav {

struct DiagnosisInputs;
struct DiagnosisResult;

struct OneSignedSlopeInputs {
  double k = 0.0;             // field residual slope on the axis (scale_factor, dimensionless)
  double k_sigma = 0.0;       // its 1-sigma (> 0)
  double x_mean = 0.0;        // the axis' mean field input (SI, nonzero)
  double c2_lab = 0.0;        // the lab's degree-2 coefficient (per SI input unit)
  double c2_lab_sigma = 0.0;  // its 1-sigma (> 0)
  double c2_simulated = 0.0;  // the quadratic SG#2 grafts on the axis (0: the lab kept a line)
  // The lab fit's responses (PolynomialFit); asymmetry weighed only when both are finite.
  double slope_per_sq = 0.0;
  double slope_per_abs = std::nan("");
  double c2_per_abs = std::nan("");
};

enum class SlopeCause { kGain, kCurvature, kAsymmetry, kUnsettled };

struct OneSignedSlope {
  double chi2_gain = 0.0, chi2_curvature = 0.0;
  double chi2_asymmetry = std::nan("");         // NaN: not weighed
  double k2_field = 0.0, k2_field_sigma = 0.0;  // the field's k2 under the curvature hypothesis
  double k2 = 0.0, k2_sigma = 0.0;              // curvature: lab and field combined
  // Asymmetry with the sensor's curvature on the axis left free (two parameters, exact): d and
  // the curvature beside it. NaN when the asymmetry is not weighed.
  double d = std::nan(""), d_sigma = std::nan("");
  double k2_beside_d = std::nan(""), k2_beside_d_sigma = std::nan("");
  // False when d's column is proportional to the curvature's (the two-parameter fit does not
  // exist): d is then the one-parameter estimate, without a curvature beside it.
  bool d_with_curvature = false;
  // The best one-parameter hypothesis (kUnsettled: none fits) and the next.
  SlopeCause best = SlopeCause::kUnsettled;
  SlopeCause runner_up = SlopeCause::kUnsettled;
  double margin = 0.0;  // chi2 of the runner-up less the best's (0 when unsettled)
};

// Throws std::invalid_argument for non-finite inputs, sigmas <= 0 or x_mean == 0.
OneSignedSlope weighOneSignedSlope(const OneSignedSlopeInputs& in);

// The term of a cause (scale_factor, scale_nonlinearity, scale_asymmetry); throws
// std::invalid_argument for kUnsettled.
TermKind slopeCauseKind(SlopeCause c);
// Its name, "unsettled" for kUnsettled.
std::string slopeCauseName(SlopeCause c);

// An axis whose input keeps one sign: |mean| >= min_ratio x its standard deviation.
bool oneSignedInput(double mean, double sd, double min_ratio = 5.0);

// For every claimed scale_factor effect whose significant elements (beyond 3 sigma) are one axis
// with a one-signed field input and the lab's degree-2 estimate there (c2_tested, or its kept
// c2 with the lab's responses): a curvature that leads by min_margin renames it
// scale_nonlinearity (k2: that axis the combined estimate, the lab's quadratic axes their c2,
// the others the lab's c2_tested; k2_missing: that axis only, less what SG#2 grafts), and the
// sensor goes to *lab_quadratic_not_listed (the effect holds the lab's quadratic); an asymmetry
// that leads renames it scale_asymmetry (k_pos = d, k_neg = -d on that axis, the gains per sign
// about the sensor's mean gain; other axes undetermined); a gain that leads keeps it and says
// why; otherwise it is listed under out->ambiguous: as the fitted scale_factor with the other
// cause as the alternative when the gain is one of the two leading causes, else renamed to the
// better of curvature and asymmetry with the other as the alternative (the lab's quadratic then
// stays listed as in the simulation: an ambiguous effect is not a claim). SG#3 is not changed: in
// the field they are the same column to first order. Not weighed when that sensor's
// scale_nonlinearity or scale_asymmetry is claimed already (the field named its even response
// itself). input_mean / input_sd: per sensor and axis, over the grid's unmasked bins.
void nameOneSignedGains(const DiagnosisInputs& in, const PerSensor<Eigen::Vector3d>& input_mean,
                        const PerSensor<Eigen::Vector3d>& input_sd, double min_margin,
                        DiagnosisResult* out, std::vector<Sensor>* lab_quadratic_not_listed);

}  // namespace graftnav
