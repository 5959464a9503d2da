#pragma once
// Gain or curvature: naming a field gain error on an axis whose input keeps one sign.
//
// On an axis whose field input stays near a large mean x_m (the accelerometer that carries
// gravity, f_z ~ -g), a gain error k and a curvature k2 (output = input + k2 input^2) are one
// column to first order: the field measures the slope at x_m, k = 2 k2 x_m. The lab tells them
// apart: its poses at -g, 0, +g leave the line's slope untouched by a curvature (the quadratic is
// even) while its degree-2 coefficient sees k2 directly. When the lab's degree test kept a line
// (the curvature was not significant at its 1 % level, PolynomialFit::c2_tested), SG#2 grafts no
// curvature, and the field's z slope at -g is then claimed as a scale factor (random_26_05:
// k_z = 1.2e-3 at 6.5 sigma from an injected k2_z = -6.6e-5 per m/s^2, which the lab estimated as
// -5.1e-5 +- 1.7e-5 and dropped).
//
// Two hypotheses for the data (lab c2_tested +- s, field k +- sigma_k), one free parameter each:
//   gain:       the gain changed between lab and field by k, no curvature:
//               chi2 = (c2_tested / s)^2
//   curvature:  c2 free, no gain change, k = 2 c2 x_m (k2_field = k / (2 x_m) +- sigma_k2):
//               chi2 = (c2_tested - k2_field)^2 / (s^2 + sigma_k2^2)
// margin = chi2_gain - chi2_curvature, 2 ln of the likelihood ratio (positive: curvature). With
// one parameter each the Occam factors are alike and left out. The curvature's k2 is the
// inverse-variance mean of the lab's and the field's estimates.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace graftnav {

struct DiagnosisInputs;
struct DiagnosisResult;

struct GainOrCurvatureInputs {
  double k = 0.0;             // field gain error on the axis (scale_factor, dimensionless)
  double k_sigma = 0.0;       // its 1-sigma (> 0)
  double x_mean = 0.0;        // the axis' mean field input (SI, nonzero)
  double c2_lab = 0.0;        // the lab's degree-2 coefficient (per SI input unit)
  double c2_lab_sigma = 0.0;  // its 1-sigma (> 0)
};

struct GainOrCurvature {
  double k2_field = 0.0, k2_field_sigma = 0.0;  // k / (2 x_mean)
  double k2 = 0.0, k2_sigma = 0.0;              // lab and field combined
  double margin = 0.0;                          // curvature over gain, 2 ln likelihood ratio
};

// Throws std::invalid_argument for non-finite inputs, sigmas <= 0 or x_mean == 0.
GainOrCurvature weighGainAgainstCurvature(const GainOrCurvatureInputs& in);

// An axis whose input keeps one sign: |mean| >= min_ratio x its standard deviation.
bool oneSignedInput(double mean, double sd, double min_ratio = 5.0);

// For every claimed scale_factor effect whose significant elements (beyond 3 sigma) are one axis
// with a one-signed field input, a lab line there (LabQuadratic::c2 zero) and the lab's degree-2
// estimate (c2_tested): margin >= min_margin renames it scale_nonlinearity (k2: that axis the
// combined estimate, the lab's quadratic axes their c2, the others the lab's c2_tested; k2_missing:
// that axis only), and the sensor goes to *lab_quadratic_not_listed (the effect holds the lab's
// quadratic); margin <= -min_margin keeps the gain and says why; in between the effect moves to
// out->ambiguous with the alternative scale_nonlinearity. SG#3 is not changed: in the field the
// two are the same column to first order. Not weighed when that sensor's scale_nonlinearity is
// claimed already (the field named its curvature itself). input_mean / input_sd: per sensor
// (0 gyro, 1 accel) and axis, over the grid's unmasked bins.
void nameOneSignedGains(const DiagnosisInputs& in, const std::array<Eigen::Vector3d, 2>& input_mean,
                        const std::array<Eigen::Vector3d, 2>& input_sd, double min_margin,
                        DiagnosisResult* out, std::vector<std::string>* lab_quadratic_not_listed);

}  // namespace graftnav
