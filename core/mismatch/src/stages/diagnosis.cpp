// The mismatch finder (diagnosis.h): its seven stages (diagnosis_stages.h) in order.
#include "graftnav/mismatch/diagnosis.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "diagnosis_stages.h"
#include "graftnav/mismatch/locate.h"

namespace graftnav {

void DiagnoseOptions::validate() const {
  joint_fit.validate();
  finder.validate();
  if (!(bin_s > 0.0 && bin_s <= 1.0))
    throw std::invalid_argument("DiagnoseOptions: bin_s = " + std::to_string(bin_s) +
                                " must be in (0, 1] s");
  if (!(margin_s >= 0.0)) throw std::invalid_argument("DiagnoseOptions: margin_s must be >= 0");
  if (!(realign_offset_s > 0.0))
    throw std::invalid_argument(
        "DiagnoseOptions: realign_offset_s = " + std::to_string(realign_offset_s) + " must be > 0");
  if (!(locate.window_s >= 2.0 * bin_s))
    throw std::invalid_argument("DiagnoseOptions: locate.window_s = " +
                                std::to_string(locate.window_s) + " must be >= 2 bins");
  time_offset.validate();
  library.validate();
  selection.validate();
  quantization.validate();
  linear_response.validate();
  if (!(max_claim_correlation > 0.0 && max_claim_correlation <= 1.0))
    throw std::invalid_argument("DiagnoseOptions: max_claim_correlation = " +
                                std::to_string(max_claim_correlation) + " must be in (0, 1]");
}

namespace {

using namespace diagnosis_detail;

// Per-bin noise variance of the largest candidate model's AR(1) noise (the same for every
// selection on this residual and library).
Vector6d binNoiseVariance(const SelectionResult& sel) {
  Vector6d bin_variance;
  for (int c = 0; c < kMismatchChannels; ++c)
    bin_variance(c) = sel.sigma(c) * sel.sigma(c) / (1.0 - sel.rho(c) * sel.rho(c));
  return bin_variance;
}

// Locate against the lower of two noise references: the quietest windows of the residual, and
// the full-model noise (an effect present everywhere leaves no quiet window). Returns the
// noise level used.
Eigen::Matrix<double, 6, 1> locateBeforeModelling(const ResidualBins& bins,
                                                  const DiagnoseOptions& opt,
                                                  const Vector6d& bin_variance,
                                                  DiagnosisResult* out) {
  out->regimes = labelRegimes(bins.x, bins.y.temperature_degC, opt.regimes);
  Eigen::Matrix<double, 6, 1> noise_ms = windowNoiseLevel(bins.r, bins.grid, opt.locate);
  for (int c = 0; c < kMismatchChannels; ++c) noise_ms(c) = std::min(noise_ms(c), bin_variance(c));
  out->located = locateResidual(bins.r, bins.grid, out->regimes, opt.locate, &noise_ms);
  return noise_ms;
}

// A record the finder no longer reads: its memory goes back now, not when the inputs die.
template <class Series>
void release(Series* series) {
  Series().swap(*series);
}

// Stages 3-7 on the binned records (the reference record is the only one they read, and only
// through selection: it is released then unless keep_reference, for SG#3 made again); returns
// SG#3's per-bin contribution. Kept apart from diagnose() so the library, the regressors and the
// passes are freed before SG#3 is built.
Eigen::MatrixXd explainAndReport(DiagnosisInputs& in, const DiagnoseOptions& opt,
                                 const TimeAlignment& alignment, const ResidualBins& bins,
                                 const RawRecordChecks& raw, bool keep_reference,
                                 DiagnosisResult* out) {
  // 3. regressors
  std::vector<Eigen::Matrix3d> C_bn = attitudeOnGrid(in, bins);
  release(&in.attitude);  // now C_bn, per bin
  RegressorState reg = initialRegressors(in, bins, alignment.pivot_s, std::move(C_bn), &out->notes);
  // 4. select
  const ExplainInputs explain{in, opt, bins, out->masked_bins};
  const SelectionPasses passes = runSelectionPasses(explain, alignment.pivot_s, &reg, &out->notes);
  const Explanation& ex = passes.explanation;
  release(&reg.at_tested_imu);  // past selection the reference is read only as bins
  if (!keep_reference) release(&in.reference);
  out->notes.insert(out->notes.end(), ex.notes.begin(), ex.notes.end());
  out->notes.insert(out->notes.end(), passes.repeat_notes.begin(), passes.repeat_notes.end());
  const Vector6d bin_variance = binNoiseVariance(ex.sel);
  // 5. locate
  const Eigen::Matrix<double, 6, 1> noise_ms = locateBeforeModelling(bins, opt, bin_variance, out);
  // 6. claims
  out->selection = ex.sel;
  const ClaimInputs claims{in, opt, bins, raw, ex, reg, alignment, passes.pivot_s};
  std::vector<Sensor> lab_quadratic_not_listed = claimEffects(claims, out);
  const ReferenceInputStats inputs = referenceInputStats(bins, out->masked_bins);
  ownAsymmetryGains(claims, inputs.mean, out);
  claimChecks(claims, inputs, &lab_quadratic_not_listed, out);
  // 7. model and report (SG#3 itself: diagnose())
  Eigen::MatrixXd sg3_contribution = modelAndReport(claims, noise_ms, bin_variance, out);
  out->in_simulation = labModelledTerms(in, lab_quadratic_not_listed);
  return sg3_contribution;
}

// The real record as the finder reads it: in.real_recording, or in.real handed over whole.
ImuRecording realRecordingOf(DiagnosisInputs* in) {
  if (!in->real_recording) return heldRecording(std::move(in->real));
  ImuRecording rec = std::move(*in->real_recording);
  in->real_recording.reset();
  release(&in->real);
  return rec;
}

// SG#3 from the simulation made again (remake_simulated) or held, the model added.
void sg3FromHeldSimulation(DiagnosisInputs& in, const Eigen::MatrixXd& sg3_contribution,
                           DiagnosisResult* out) {
  if (in.simulated.empty()) {
    in.simulated = in.remake_simulated(in.reference);
    release(&in.reference);
    if (in.simulated.empty())
      throw std::runtime_error("diagnose: remake_simulated returned an empty record");
  }
  out->sg3 = std::move(in.simulated);
  addBinnedContributionInPlace(out->grid, sg3_contribution, &out->sg3);
}

}  // namespace

DiagnosisResult diagnose(const DiagnosisInputs& in, const DiagnoseOptions& opt) {
  return diagnose(DiagnosisInputs(in), opt);
}

DiagnosisResult diagnose(DiagnosisInputs&& in, const DiagnoseOptions& opt_in) {
  opt_in.validate();
  const bool real_empty = in.real_recording ? in.real_recording->samples == 0 : in.real.empty();
  const bool simulated_empty =
      in.simulated_recording ? in.simulated_recording->samples == 0 : in.simulated.empty();
  if (in.reference.empty() || simulated_empty || real_empty)
    throw std::invalid_argument(
        "diagnose: reference, simulated and real records must be non-empty");
  DiagnosisResult out;
  out.case_name = in.case_name;
  out.simulation_kind = in.simulation_kind;
  TimeAlignment alignment = alignTime(in, realRecordingOf(&in), opt_in, &out);  // 1. align time
  // 2. grid and residual
  std::optional<ImuRecording> simulated = std::move(in.simulated_recording);
  in.simulated_recording.reset();
  const bool simulated_held = !simulated;
  if (simulated_held) simulated = viewedRecording(in.simulated);
  out.grid = finderGrid(in, *simulated, alignment.real(), alignment.pivot_s, opt_in, &out.notes);
  const DiagnoseOptions opt = optionsOnGrid(in, *simulated, out.grid, opt_in);
  const ResidualBins bins = binResidual(in, *simulated, alignment, out.grid, &out);
  const RawRecordChecks raw = rawRecordChecks(*simulated, alignment, opt);
  // Past here the finder reads the real record and the simulation only as bins.
  alignment.releaseRecords();
  if (simulated_held) {
    simulated.reset();
    if (in.remake_simulated) release(&in.simulated);
  }
  const bool remakes = simulated_held && in.simulated.empty();  // SG#3 from the reference
  const Eigen::MatrixXd sg3_contribution =
      explainAndReport(in, opt, alignment, bins, raw, remakes, &out);
  if (simulated_held) {
    sg3FromHeldSimulation(in, sg3_contribution, &out);
  } else {
    out.sg3_recording = withBinnedContribution(std::move(*simulated), out.grid, sg3_contribution);
  }
  return out;
}

}  // namespace graftnav
