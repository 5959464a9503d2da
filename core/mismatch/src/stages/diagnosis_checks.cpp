// The finder's checks on its claims that do not change the model: the reference IMU's share in
// a scale factor, the names of one-signed gains, value lattices, correlations and ranges.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "diagnosis_stages.h"
#include "graftnav/mismatch/claim_checks.h"
#include "graftnav/mismatch/gain_or_curvature.h"

namespace graftnav::diagnosis_detail {

namespace {

// The simulation is built on the reference signal, so it carries the reference IMU's own gain
// error, which the real tested IMU does not: a claimed scale factor of a few times the
// reference's stated scale uncertainty may be partly or wholly the reference's (its sign
// reversed). The gate (a) allows 3 sigma of it; the reader is told how many sigma the claim is.
void noteReferenceScaleShare(const DiagnosisInputs& in, double share_limit, DiagnosisResult* out) {
  for (Effect& e : out->effects) {
    if (e.kind() != TermKind::scale_factor) continue;
    const std::optional<double>& ref_sigma = in.priors[sensorOf(e.sensor)].reference_scale_sigma;
    if (!ref_sigma || !(*ref_sigma > 0.0)) continue;
    const std::vector<double>& k = e.parameters[0].values;
    const double k_max = std::abs(*std::max_element(
        k.begin(), k.end(), [](double a, double b) { return std::abs(a) < std::abs(b); }));
    const double ratio = k_max / *ref_sigma;
    if (ratio >= share_limit) continue;
    e.explanation += fmt::format(
        "; the largest |k| is {:.1f} x the reference IMU's stated scale uncertainty ({:.3g} ppm "
        "1-sigma, its profile): the simulation inherits the reference's own gain error, so this "
        "may be partly the reference's (sign reversed), not the tested IMU's",
        ratio, 1e6 * *ref_sigma);
  }
}

// A value lattice only beyond the printed resolution and with a resolvable noise
// (quantization_evidence.h): claimed, or its detection limit.
void claimQuantization(const QuantizationCheck& q, DiagnosisResult* out) {
  out->quantization_checks.push_back(q);
  Effect e(termSpec(TermKind::quantization), scopeOf(q.sensor));
  EffectParameter p;
  p.key = e.spec->parameters[0].key;
  if (q.anyClaimed()) {
    e.evidence_method = "value_lattice";
    for (int a = 0; a < 3; ++a) {
      p.values.push_back(q.claimed[a] ? q.step(a) : 0.0);
      p.sigma.push_back(q.claimed[a] ? 1e-6 * q.step(a) : kNaN);
    }
    e.parameters.push_back(p);
    e.explanation = std::string("the real ") + sensorName(q.sensor) +
                    " increments are whole multiples of a step "
                    "coarser than the file's printed resolution, and its noise is resolvable "
                    "against the white noise; the simulation's are not (" +
                    q.summary() + ")";
    out->effects.push_back(e);
  } else if (!q.simulation_on_same_lattice) {
    e.evidence_method = "detection_limit";
    e.delta_bic = e.cv_gain = kNaN;
    for (int a = 0; a < 3; ++a) p.values.push_back(q.detectable_step(a));
    p.sigma.assign(3, kNaN);
    e.parameters.push_back(p);
    e.explanation = q.summary();
    out->detection_limits.push_back(e);
  }
}

}  // namespace

RawRecordChecks rawRecordChecks(const ImuRecording& simulated, const TimeAlignment& alignment,
                                const DiagnoseOptions& opt) {
  RawRecordChecks raw;
  if (opt.detect_quantization)
    for (const Sensor s : kSensors)
      raw.quantization.push_back(
          checkQuantization(alignment.real(), simulated, s, opt.quantization));
  return raw;
}

ReferenceInputStats referenceInputStats(const ResidualBins& bins, const std::vector<char>& masked) {
  Eigen::MatrixXd ref_inputs(bins.n(), kMismatchChannels);
  ref_inputs << bins.x.omega_rad_s, bins.x.f_m_s2;
  ReferenceInputStats st;
  st.mean = meanOf(ref_inputs, masked);
  st.sd = rmsOf(ref_inputs.rowwise() - st.mean.transpose(), masked);
  return st;
}

void claimChecks(const ClaimInputs& c, const ReferenceInputStats& inputs,
                 std::vector<Sensor>* lab_quadratic_not_listed, DiagnosisResult* out) {
  const DiagnosisInputs& in = c.in;
  noteReferenceScaleShare(in, c.opt.finder.reference_scale_share_limit, out);
  // A gain on an axis whose input keeps one sign may be the lab's unfitted curvature or an
  // asymmetry its poses folded into a quadratic (gain_or_curvature.h): the lab's degree-2
  // coefficient decides the name, or says it cannot.
  const PerSensor<Eigen::Vector3d> input_mean{{inputs.mean.head<3>(), inputs.mean.tail<3>()}};
  const PerSensor<Eigen::Vector3d> input_sd{{inputs.sd.gyro, inputs.sd.accel}};
  nameOneSignedGains(in, input_mean, input_sd, c.opt.selection.min_name_margin, out,
                     lab_quadratic_not_listed);
  const SelectionResult& sel = c.ex.sel;
  out->nuisance_bias = sel.nuisance.theta.head<6>();
  if (sel.nuisance.theta.size() == 12) out->nuisance_drift = 2.0 * sel.nuisance.theta.segment<6>(6);
  // Claims: a value lattice (quantization_evidence.h); then correlations, plausible ranges and
  // identifiability (claim_checks.h). Neither changes the model.
  for (const QuantizationCheck& q : c.raw.quantization) claimQuantization(q, out);
  ClaimCheckInputs cc;
  cc.terms = &c.ex.terms;
  cc.selection = &sel;
  cc.reference = &c.bins.x;
  cc.residual = &c.bins.r;
  cc.masked = &out->masked_bins;
  cc.bin_s = c.bins.grid.bin_s;
  cc.lab_calibrated = anyLabCalibration(in);
  cc.ranges = in.tested_plausible_ranges;
  checkClaims(cc, c.opt, out);
}

}  // namespace graftnav::diagnosis_detail
