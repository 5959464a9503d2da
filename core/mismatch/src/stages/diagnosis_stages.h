#pragma once
// The mismatch finder's stages, the seven of diagnosis.h, private to the module. diagnose()
// (diagnosis.cpp) runs them in order over typed values: each stage reads what the earlier ones
// returned and returns its own result; the report (DiagnosisResult) is the only thing several
// stages write, each its part.
//
//   1. align time        alignTime -> TimeAlignment (cross-correlation offset, realignment)
//   2. grid and residual finderGrid -> GridSpec, binResidual -> ResidualBins, rawRecordChecks
//   3. regressors        attitudeOnGrid, initialRegressors -> RegressorState (at a pivot)
//   4. select            runSelectionPasses -> SelectionPasses: explainAt -> Explanation (library,
//                        selection, second pass, lab gates, joint fit) and the passes it calls
//                        for (time pivot, mounting rotation, lever arm)
//   5. locate            locateBeforeModelling (diagnosis.cpp)
//   6. claims            claimEffects, ownAsymmetryGains, claimChecks
//   7. model and report  modelAndReport, labModelledTerms

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/term_effect.h"
#include "graftnav/mismatch/term_spec.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/nav/types.h"

namespace graftnav::diagnosis_detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- 1. align time ----
struct TimeAlignment {
  double pivot_s = 0.0;    // pivot of the time_offset regressor (s)
  double realign_s = 0.0;  // taken out of the real record's tags before binning (0: none)
  ImuRecording as_tagged;  // the real record as recorded
  ImuRecording realigned;  // the same with its tags moved by realign_s (unset: none)
  const ImuRecording& real() const { return realign_s != 0.0 ? realigned : as_tagged; }
  // The real record is read only as bins from here on: its passes (and what they hold) go.
  void releaseRecords() { as_tagged = realigned = ImuRecording(); }
};
// The real record is `real` (in.real or in.real_recording, as realRecordingOf hands it over).
TimeAlignment alignTime(const DiagnosisInputs& in, ImuRecording real, const DiagnoseOptions& opt,
                        DiagnosisResult* out);

// ---- 2. grid and residual ----
// `simulated`: in.simulated or in.simulated_recording, as a recording (so are all the stages').
GridSpec finderGrid(const DiagnosisInputs& in, const ImuRecording& simulated,
                    const ImuRecording& real, double pivot_s, const DiagnoseOptions& opt,
                    std::vector<std::string>* notes);
// The options with what depends on the grid and the graft (slow-noise blocks, replay period).
DiagnoseOptions optionsOnGrid(const DiagnosisInputs& in, const ImuRecording& simulated,
                              const GridSpec& grid, const DiagnoseOptions& opt);

struct ResidualBins {
  GridSpec grid;
  BinnedImu x, s, y;   // reference, simulated and real on the grid
  Eigen::MatrixXd r;   // n x 6, real - simulated, zero on masked bins
  Eigen::MatrixXd r0;  // the same for the real record as tagged (only with a realignment)
  int n() const { return grid.count; }
};
// Also marks the bins overlapping sampling gaps (out->masked_bins, masked_spans, a note).
ResidualBins binResidual(const DiagnosisInputs& in, const ImuRecording& simulated,
                         const TimeAlignment& alignment, const GridSpec& grid,
                         DiagnosisResult* out);
// What the finder reads from the raw samples of the real record and the simulation besides
// their bins: the value lattices of both triads (quantization_evidence.h), gyro then accel.
// Taken before the records are released; claimChecks turns them into claims.
struct RawRecordChecks {
  std::vector<QuantizationCheck> quantization;  // empty when the check is off
};
RawRecordChecks rawRecordChecks(const ImuRecording& simulated, const TimeAlignment& alignment,
                                const DiagnoseOptions& opt);

// ---- 3. regressors ----
struct RegressorState {
  // What the time offset shifts: the reference as the lab-calibrated tested IMU responds to it,
  // applied sample by sample as the reference is read (empty: the reference itself).
  ImuSampleMap lab_response;
  ImuSeries at_tested_imu;  // the reference moved by a fitted lever arm (empty: not moved)
  RegressorInputs ri;
  double motion_pivot_s = kNaN;  // the pivot ri's motion regressors were last built at
  const ImuSeries& testedForce(const DiagnosisInputs& in) const {
    return at_tested_imu.empty() ? in.reference : at_tested_imu;
  }
};
// The reference body's attitude at the bin middles (nav to body), for the Earth and gravity
// terms; empty when they are not tested (no initial state, or a recorded reference).
std::vector<Eigen::Matrix3d> attitudeOnGrid(const DiagnosisInputs& in, const ResidualBins& bins);
// The pivot-independent inputs (lab response, temperatures, the attitude C_bn from
// attitudeOnGrid); notes to `notes`. Ends by building the motion regressors at pivot_s.
RegressorState initialRegressors(const DiagnosisInputs& in, const ResidualBins& bins,
                                 double pivot_s, std::vector<Eigen::Matrix3d> C_bn,
                                 std::vector<std::string>* notes);
// The motion regressors at pivot pv (x(t - pv)); nothing when already built there. A fresh state
// (motion_pivot_s NaN) also notes the lever arm's angular-acceleration windows.
void buildMotionRegressors(const DiagnosisInputs& in, const ResidualBins& bins, double pv,
                           RegressorState* reg, std::vector<std::string>* notes);

// ---- 4. select ----
struct Explanation {
  std::vector<CandidateTerm> terms;
  SelectionResult sel;
  Eigen::MatrixXd joint_model;         // the Ceres model's prediction when the joint fit moved
  std::vector<std::string> notes;      // this pass's notes for the report
  std::vector<int> calibration_gated;  // terms the lab gates held back as calibration error
  double tau_joint_s = kNaN;           // the joint fit's tau when it converged
};
// The read-only inputs of every explanation pass.
struct ExplainInputs {
  const DiagnosisInputs& in;
  const DiagnoseOptions& opt;
  const ResidualBins& bins;
  const std::vector<char>& masked;
};
Explanation explainAt(const ExplainInputs& ex, double pv, RegressorState* reg,
                      std::vector<std::string>* report_notes);
struct SelectionPasses {
  Explanation explanation;
  double pivot_s = 0.0;                   // the time_offset pivot of the last pass
  std::vector<std::string> repeat_notes;  // why each further pass ran
};
SelectionPasses runSelectionPasses(const ExplainInputs& ex, double pivot_s, RegressorState* reg,
                                   std::vector<std::string>* report_notes);
SelectionResult applyLabGates(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                              const DiagnosisInputs& in, const DiagnoseOptions& opt,
                              const GridSpec& grid, SelectionResult sel,
                              std::vector<std::string>* notes, std::vector<int>* calibration_gated);

// ---- 6. claims (5, locate: diagnosis.cpp) ----
struct ClaimInputs {
  const DiagnosisInputs& in;
  const DiagnoseOptions& opt;
  const ResidualBins& bins;
  const RawRecordChecks& raw;
  const Explanation& ex;
  const RegressorState& reg;
  const TimeAlignment& alignment;
  double pivot_s;
};
// Effects, ambiguous terms, detection limits, the realignment's offset; returns the sensors
// whose lab quadratic is not listed as in the simulation (labModelledTerms).
std::vector<Sensor> claimEffects(const ClaimInputs& c, DiagnosisResult* out);
// The reference inputs (true rates and specific forces): their means over the unmasked bins (the
// gains at the drive's mean input) and their RMS about it (the one-signed axes).
struct ReferenceInputStats {
  Vector6d mean = Vector6d::Zero();
  ChannelRms sd;
};
ReferenceInputStats referenceInputStats(const ResidualBins& bins, const std::vector<char>& masked);
// Scale asymmetry's own gains per sign (fitted on tested minus reference).
void ownAsymmetryGains(const ClaimInputs& c, const Vector6d& ref_input_mean, DiagnosisResult* out);
// Reference-scale shares, one-signed gains, nuisance, quantization lattices, correlations and
// ranges.
void claimChecks(const ClaimInputs& c, const ReferenceInputStats& inputs,
                 std::vector<Sensor>* lab_quadratic_not_listed, DiagnosisResult* out);

// ---- 7. model and report ----
// Returns SG#3's per-bin contribution to the simulation (n x 6, addBinnedContribution).
Eigen::MatrixXd modelAndReport(const ClaimInputs& c, const Eigen::Matrix<double, 6, 1>& noise_ms,
                               const Vector6d& bin_variance, DiagnosisResult* out);
void holdoutCheck(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                  const DiagnoseOptions& opt, DiagnosisResult* out);

// ---- shared helpers (diagnosis_effects.cpp) ----
Vector6d meanOf(const Eigen::MatrixXd& r, const std::vector<char>& masked);
ChannelRms rmsOf(const Eigen::MatrixXd& r, const std::vector<char>& masked, int offset = 0);
void zeroMaskedRows(const std::vector<char>& masked, Eigen::MatrixXd* r);
void zeroMaskedRows(const std::vector<char>& masked, std::vector<CandidateTerm>* terms);
Eigen::MatrixXd nuisanceOnlyFit(const Eigen::MatrixXd& r, int a, int b, bool drift,
                                const std::vector<char>& masked);
double sharedRotationLabSigma(const DiagnosisInputs& in, int axis);
// Whether either sensor has a lab calibration matrix uncertainty.
bool anyLabCalibration(const DiagnosisInputs& in);
double labRotationSigma(const std::optional<Eigen::Matrix3d>& M_sigma, int axis);
bool sensorsOwnQuadratic(const LabQuadratic& lab, double gate_sigmas, Effect* e);
std::string limitReason(const CandidateTerm& t, const SelectionResult& sel, double bin_s, int n);
std::vector<Effect> labModelledTerms(const DiagnosisInputs& in,
                                     const std::vector<Sensor>& not_listed);

}  // namespace graftnav::diagnosis_detail
