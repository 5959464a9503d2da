// Shared helpers of the finder's stages: masked means and RMS, the lab's rotation uncertainty,
// and the report's text for limits and lab-modelled terms.
#include <fmt/core.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "diagnosis_stages.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav::diagnosis_detail {

// Column means of r over its unmasked rows (zero when all are masked).
Vector6d meanOf(const Eigen::MatrixXd& r, const std::vector<char>& masked) {
  Vector6d sum = Vector6d::Zero();
  int rows = 0;
  for (Eigen::Index i = 0; i < r.rows(); ++i) {
    if (masked[i]) continue;
    sum += r.row(i).transpose();
    ++rows;
  }
  return rows > 0 ? Vector6d(sum / rows) : sum;
}

// RMS per channel over the rows of r that are not masked (masked[offset + i] != 0: a bin
// overlapping a sampling gap).
ChannelRms rmsOf(const Eigen::MatrixXd& r, const std::vector<char>& masked, int offset) {
  ChannelRms out;
  Vector6d sum = Vector6d::Zero();
  int rows = 0;
  for (Eigen::Index i = 0; i < r.rows(); ++i) {
    if (masked[offset + i]) continue;
    sum += r.row(i).transpose().cwiseAbs2();
    ++rows;
  }
  if (rows == 0) return out;
  for (int c = 0; c < 3; ++c) {
    out.gyro(c) = std::sqrt(sum(c) / rows);
    out.accel(c) = std::sqrt(sum(3 + c) / rows);
  }
  return out;
}

// Excludes the masked bins from every fit: their residual and regressor values are set to zero,
// so they add nothing to a Gram matrix or a sum of squares.
void zeroMaskedRows(const std::vector<char>& masked, Eigen::MatrixXd* r) {
  for (Eigen::Index i = 0; i < r->rows(); ++i)
    if (masked[i]) r->row(i).setZero();
}
void zeroMaskedRows(const std::vector<char>& masked, std::vector<CandidateTerm>* terms) {
  for (CandidateTerm& t : *terms)
    for (RegressorColumn& col : t.columns)
      for (int c = 0; c < kMismatchChannels; ++c)
        if (col.actsOn(c))
          for (Eigen::Index i = 0; i < col.channel[c].size(); ++i)
            if (masked[col.first_row + i]) col.channel[c](i) = 0.0;
}

// Per-channel least-squares constant + linear drift (the nuisance alone) fitted over bins
// [a, b) with the same ramp as the library, evaluated on all bins.
Eigen::MatrixXd nuisanceOnlyFit(const Eigen::MatrixXd& r, int a, int b, bool drift,
                                const std::vector<char>& masked) {
  const int n = static_cast<int>(r.rows());
  const Eigen::VectorXd ramp =
      drift ? Eigen::VectorXd::LinSpaced(n, -1.0, 1.0).eval() : Eigen::VectorXd::Zero(n).eval();
  Eigen::MatrixXd A(b - a, 2);
  A.col(0).setOnes();
  A.col(1) = ramp.segment(a, b - a);
  for (int i = a; i < b; ++i)
    if (masked[i]) A.row(i - a).setZero();  // r is zero there too
  Eigen::MatrixXd out(n, r.cols());
  for (Eigen::Index c = 0; c < r.cols(); ++c) {
    const Eigen::Vector2d coef = A.colPivHouseholderQr().solve(r.col(c).segment(a, b - a));
    out.col(c) = coef(0) * Eigen::VectorXd::Ones(n) + coef(1) * ramp;
  }
  return out;
}

// 1-sigma of the rotation about `axis` that a lab calibration leaves in a sensor triad's frame:
// a rotation is indistinguishable from the antisymmetric part of the cross-axis terms, phi_z from
// (M_yx - M_xy) / 2 etc., so sqrt(s_xy^2 + s_yx^2) / 2. Zero without lab data.
double labRotationSigma(const std::optional<Eigen::Matrix3d>& M_sigma, int axis) {
  if (!M_sigma) return 0.0;
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  return 0.5 * std::hypot((*M_sigma)(i, j), (*M_sigma)(j, i));
}

// The lab rotation uncertainty of a mounting rotation shared by both sensors: the less certain
// sensor's (labRotationSigma).
double sharedRotationLabSigma(const DiagnosisInputs& in, int axis) {
  return std::max(labRotationSigma(in.priors[Sensor::gyro].lab_M_sigma, axis),
                  labRotationSigma(in.priors[Sensor::accel].lab_M_sigma, axis));
}

bool anyLabCalibration(const DiagnosisInputs& in) {
  return in.priors[Sensor::gyro].lab_M_sigma.has_value() ||
         in.priors[Sensor::accel].lab_M_sigma.has_value();
}

// Turns a scale_nonlinearity effect fitted on the residual (the part SG#2 lacks) into the
// sensor's own k2 = c2 (lab) + k2_missing, sigma combined, keeping the fitted part as
// k2_missing. Returns whether some axis is non-zero beyond gate_sigmas.
bool sensorsOwnQuadratic(const LabQuadratic& lab, double gate_sigmas, Effect* e) {
  EffectParameter missing = e->parameters[0];
  missing.key = "k2_missing";
  EffectParameter& own = e->parameters[0];
  bool beyond = false;
  for (int a = 0; a < 3; ++a) {
    own.values[a] = missing.values[a] + lab.c2(a);
    own.sigma[a] = std::hypot(missing.sigma[a], lab.c2_sigma(a));
    if (std::isfinite(own.sigma[a])) beyond |= std::abs(own.values[a]) > gate_sigmas * own.sigma[a];
  }
  e->parameters.push_back(missing);
  return beyond;
}

// DiagnosisResult::in_simulation: the lab's quadratic per sensor, when some axis has one, except
// for the sensors in `not_listed`: a claimed scale_nonlinearity already reports the sensor's own
// k2 (lab c2 included), and a residual that cancels the lab's c2 says it is not the sensor's.
std::vector<Effect> labModelledTerms(const DiagnosisInputs& in,
                                     const std::vector<Sensor>& not_listed) {
  std::vector<Effect> out;
  for (const Sensor s : kSensors) {
    const std::optional<LabQuadratic>& quad = in.priors[s].lab_quadratic;
    if (!quad || (quad->c2.array() == 0.0).all()) continue;
    if (std::find(not_listed.begin(), not_listed.end(), s) != not_listed.end()) continue;
    const LabQuadratic& q = *quad;
    EffectParameter k2;
    k2.key = "k2";
    std::string axes;
    for (int a = 0; a < 3; ++a) {
      k2.values.push_back(q.c2(a));
      k2.sigma.push_back(q.c2(a) != 0.0 ? q.c2_sigma(a) : NAN);
      if (q.c2(a) != 0.0)
        axes += fmt::format("{}{} {:.3g} +- {:.2g}", axes.empty() ? "" : ", ", "xyz"[a], q.c2(a),
                            q.c2_sigma(a));
    }
    Effect e(termSpec(TermKind::scale_nonlinearity), scopeOf(s));
    e.parameters.push_back(k2);
    e.evidence_method = "lab_degree_test";
    e.explanation = fmt::format(
        "the lab calibration's fitting function (seed Eq. 21) took a quadratic on {} ({}): the "
        "tested {} bends, and SG#2 already grafts it, so the field residual does not show it "
        "(a scale asymmetry looks the same on the lab's -g/0/+g poses)",
        axes.find(',') == std::string::npos ? "one axis" : "these axes", axes, sensorNoun(s));
    out.push_back(e);
  }
  return out;
}

// Why a candidate left out of the model is below what this record shows: the limit of a column
// scales as the residual's noise over the column's excitation (its RMS variation about its mean
// times sqrt(record length)); the reader sees which of the two sets it.
std::string limitReason(const CandidateTerm& t, const SelectionResult& sel, double bin_s, int n) {
  double excitation = 0.0, noise = 0.0;
  for (const RegressorColumn& col : t.columns)
    for (int c = 0; c < kMismatchChannels; ++c) {
      if (!col.actsOn(c)) continue;
      const Eigen::VectorXd u = col.dense(c);
      excitation = std::max(excitation, std::sqrt((u.array() - u.mean()).square().mean()));
      noise = std::max(noise, sel.sigma(c) / (1.0 - std::min(sel.rho(c), 0.99)));
    }
  return fmt::format(
      "not shown by this motion below the limit: its most excited column varies by {:.3g} (RMS "
      "about its mean, SI) over {:.0f} s against a residual noise of {:.3g} per {:.3g}-s bin "
      "(long-run); the limit falls as 1 / (excitation x sqrt(duration))",
      excitation, n * bin_s, noise, bin_s);
}
}  // namespace graftnav::diagnosis_detail
