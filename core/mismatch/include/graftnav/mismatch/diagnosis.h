#pragma once
// The mismatch finder: given the reference signals x, a simulation of the tested IMU and the
// tested IMU's real recording, diagnose() runs seven stages (src/stages/diagnosis_stages.h,
// docs/mismatch-method.md, in the same order and numbering):
//   1. align time: the real record's time offset by cross-correlation (time_offset.h), taken out
//      of its tags when large; the pivot of the time_offset regressor;
//   2. grid and residual: all three records binned on one grid (common_grid.h), the residual
//      r = real - simulated per channel, bins over sampling gaps masked; the raw records' value
//      lattices;
//   3. regressors: what the candidate terms are built from (candidate_terms.h), at the pivot;
//   4. select: the candidate library (term_spec.h), the selection (term_selection.h), the lab
//      gates and the joint fit of the time offset (joint_fit.h), and the passes they call for;
//   5. locate: where the residual departs from noise (locate.h);
//   6. claims: effects, ambiguous names, detection limits, and the checks on them (claim_checks.h,
//      gain_or_curvature.h, quantization_evidence.h);
//   7. model and report: SG#3 = simulation + the claimed terms (each channel's record mean of the
//      model left out: it is confounded with the constant bias, which is not grafted), residual
//      RMS before/after on the whole record and on the second half with a model fitted on the
//      first half only, and what the model leaves above noise, listed as unexplained.

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/finder_options.h"
#include "graftnav/io/imu_recording.h"
#include "graftnav/mismatch/joint_fit.h"
#include "graftnav/mismatch/linear_response.h"
#include "graftnav/mismatch/locate.h"
#include "graftnav/mismatch/quantization_evidence.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/imu/plausible_ranges.h"
#include "graftnav/mismatch/term_correlation.h"
#include "graftnav/mismatch/term_kind.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/mismatch/time_offset.h"
#include "graftnav/mismatch/wander.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// The quadratic coefficient per axis of the lab's fitting polynomial (measured = c0 + c1 x +
// c2 x^2, SI; calibration_result.h PolynomialFit), which SG#2 grafts; zero on axes fitted with
// degree 1.
struct LabQuadratic {
  Eigen::Vector3d c2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d c2_sigma = Eigen::Vector3d::Zero();
  // The degree-2 coefficient the lab's degree test weighed on every axis, kept or not
  // (PolynomialFit::c2_tested; NaN: the points support no quadratic): evidence for naming a
  // field gain on a one-signed axis a curvature (gain_or_curvature.h).
  Eigen::Vector3d c2_tested = Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Vector3d c2_tested_sigma = Eigen::Vector3d::Constant(std::nan(""));
  // The lab fit's response to an asymmetry d |x| (slope: d * slope_per_abs, c2_tested:
  // d * c2_tested_per_abs) and to a curvature it did not fit (slope: k2 * slope_per_sq); see
  // PolynomialFit. NaN slope_per_sq counts as 0 (symmetric poses); NaN asymmetry responses: an
  // asymmetry is not weighed (gain_or_curvature.h).
  Eigen::Vector3d slope_per_abs = Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Vector3d slope_per_sq = Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Vector3d c2_tested_per_abs = Eigen::Vector3d::Constant(std::nan(""));
};

// What is known about one sensor triad of the tested IMU before its field record is explained:
// its lab calibration and the reference IMU's stated scale uncertainty. Every field is optional.
struct SensorPriors {
  // Lab Allan figures. When given, the slow bias wander that two independent realizations (lab
  // graft and field) of that noise leave in the residual is noise, not missing physics: a
  // bias_instability term is claimed only beyond it, and a channel whose fitted wander lies
  // within it is not listed as unexplained (see WanderCheck).
  std::optional<LabNoiseFigures> lab_noise;
  // 1-sigma of the lab calibration matrix M (calibration_result.h). When given, a scale_factor
  // or non_orthogonality term is claimed only if some element exceeds 3 x sqrt(fit sigma^2 +
  // lab sigma^2): a smaller one is the lab calibration's own error, not missing physics.
  std::optional<Eigen::Matrix3d> lab_M_sigma;
  // The lab calibration matrix M (scale and cross-axis). The tested IMU applies it to the motion
  // it measured at t - tau, so the time offset's signal in the residual is M (x(t - tau) - x(t)),
  // not x(t - tau) - x(t); with a MEMS scale of 1e-3 the difference is invisible with
  // independent noise but not under common random numbers.
  std::optional<Eigen::Matrix3d> lab_M;
  // 1-sigma scale-factor uncertainty of the reference IMU (its profile in case.yaml, a
  // fraction). The simulation is built on the reference signal, so it carries the reference's own
  // scale error; with a lab calibration a scale_factor is claimed only beyond 3 x sqrt(fit
  // sigma^2 + lab sigma^2 + this^2) (under common random numbers a navigation-grade reference's
  // 26 ppm was claimed on a null case).
  std::optional<double> reference_scale_sigma;
  // The lab polynomial's quadratic term. When given, scale_nonlinearity reports the sensor's own
  // k2 (the lab's c2 plus the missing part the residual shows, k2_missing) and is claimed only if
  // that is non-zero beyond 3 sigma: a residual quadratic that only cancels SG#2's c2 (e.g. a
  // scale asymmetry folded into c2 on the rate table) is the simulation's artefact, modelled in
  // SG#3 but not a non-linearity of the sensor. Nor is it claimed when k2_missing is within
  // 3 x sqrt(fit sigma^2 + c2_sigma^2) on every axis: the lab's c2 is off by no more than its own
  // uncertainty (calibration error, as for scale_factor; modelled in SG#3).
  std::optional<LabQuadratic> lab_quadratic;
};

struct DiagnosisInputs {
  std::string case_name;
  ImuSeries reference;  // reference IMU: the true inputs x, reference body frame
  ImuSeries simulated;  // the simulation of the tested IMU (SG#2, or reference + static bias);
                        // its temperature column, when every sample has one, is the temperature
                        // behind its own bias (see RegressorInputs::simulated_temperature_degC)
  ImuSeries real;       // the tested IMU's field recording
  // The same record read as passes (e.g. its file, case/file_streams.h), when it is not held:
  // then `real` is left empty and the finder holds of it only what it makes at the bin rate.
  std::optional<ImuRecording> real_recording;
  std::string simulation_kind;  // e.g. "SG#2" or "reference + static bias", for the report
  // Initial attitude and position of the reference body (enables the earth_rotation_omitted and
  // gravity_model terms).
  std::optional<NavState> initial_state;
  // Omitted navigation physics (earth_rotation_omitted, gravity_model) can only be missing from a
  // simulated reference; a recorded reference IMU senses both. Set for simulated cases.
  bool reference_is_simulated = false;
  // Attitude of the reference body along the record (e.g. truth.nav of a simulated case); when
  // empty, the attitude is integrated from initial_state with the reference gyros (Earth rate
  // removed).
  NavSeries attitude;
  // When `attitude` is empty: reads it (e.g. truth.nav), called once the records are binned, so
  // the attitude is not held next to them. Empty: none.
  std::function<NavSeries()> read_attitude;
  // SG#2 replays the lab's static record (its bias wander included) tiled forward and backward
  // (GraftedCase): its length and the tiling time at the reference's first sample start. The
  // slow terms' wander model then holds that replay next to the field's own walk. 0: none.
  double graft_static_record_s = 0.0;
  double graft_start_offset_s = 0.0;
  // What is known beforehand about each sensor triad of the tested IMU (SensorPriors).
  PerSensor<SensorPriors> priors;
  // The tested IMU's plausible ranges (its profile's, or its grade's class defaults). A fitted
  // value outside them is not claimed as that physics (claim_checks.h). Unset: no range check.
  std::optional<PlausibleRanges> tested_plausible_ranges;
  // The simulation made again from the reference record, sample for sample the same as
  // `simulated` (e.g. SG#2 grafted again from the lab calibration). When set, diagnose() on
  // inputs it may consume releases `simulated` once it is binned and calls this for SG#3 at the
  // end, so the finder holds one IMU record (the reference) through selection. Empty: the
  // simulation is kept.
  std::function<ImuSeries(const ImuSeries& reference)> remake_simulated;
  // The simulation read as passes (e.g. SG#2 grafted block by block into a spool,
  // diagnosis_setup.h), when it is not held: then `simulated` is left empty, remake_simulated is
  // not called, and SG#3 is this recording plus the model (DiagnosisResult::sg3_recording).
  std::optional<ImuRecording> simulated_recording;
};

struct DiagnoseOptions {
  double bin_s = 0.05;    // averaging bin (s)
  double margin_s = 1.0;  // dropped at both ends of the overlap (room for the time shift)
  // A cross-correlation time offset larger than this is taken out of the real record's tags
  // before binning (the joint fit shifts the other terms only to first order); the reported
  // time_offset adds the fitted remainder.
  double realign_offset_s = 0.1;
  TimeOffsetOptions time_offset;
  CandidateLibraryOptions library;
  SelectionOptions selection;
  RegimeOptions regimes;
  LocateOptions locate;
  bool holdout = true;         // first half fit, second half check
  double slow_block_s = 60.0;  // block of the slow-noise check (term_selection.h); 0 = off
  bool detect_quantization = true;
  QuantizationEvidenceOptions quantization;  // when a value lattice is claimed (header there)
  LinearResponseOptions linear_response;     // the excitation the split of E is stated for
  // Two claimed terms whose columns correlate above this are reported with the correlation
  // (claim_checks.h); the report lists every pair anyway.
  double max_claim_correlation = 0.95;
  // When time_offset is selected, refit the final model with tau as a non-linear parameter in a
  // ceres::Problem (joint_fit.h); the reported parameters and covariances are then Ceres'.
  bool ceres_joint_fit = true;
  JointFitOptions joint_fit;
  FinderOptions finder;  // the finder's own gates, pass counts and minimum sizes
  void validate() const;
};

// One named parameter of an effect (values row-major for matrices; sigma NaN/inf = unknown).
struct EffectParameter {
  std::string key;
  std::vector<double> values;
  std::vector<double> sigma;
  bool scalar = false;  // written as a number, not a list
  std::string text;     // for string-valued parameters (vibration regressor)
};

struct Effect {
  Effect() = default;
  Effect(const TermSpec& term, SensorScope scope) : spec(&term), sensor(scope) {}
  const TermSpec* spec = nullptr;  // the term it names (term_spec.h): its name and parameters
  SensorScope sensor = SensorScope::both;
  std::vector<EffectParameter> parameters;
  double delta_bic = 0.0;
  double cv_gain = 0.0;
  std::string explanation;
  std::string evidence_method = "bic+blocked_cv";  // or "value_lattice"
  TermKind kind() const;
  const char* name() const;  // as diagnosis.json writes it ("" without a spec)
};

// A selected term whose shape the data do not settle (term_selection.h, step 5): modelled in SG#3
// under the name the selection chose, not claimed. `effect` is that term as fitted; `alternative` the
// other shape's name and `name_margin` the evidence of the fitted shape over it (2 ln Bayes
// factor, below SelectionOptions::min_name_margin; negative when the other shape is the better
// one, by less than the margin: the term stays as forward selection chose it).
struct AmbiguousEffect {
  Effect effect;
  const TermSpec* alternative = nullptr;
  double name_margin = 0.0;
};

// A fitted term whose value no sensor of the class can have (plausible_ranges.h): modelled in
// SG#3, not claimed as that physics. `absorbing` names the fitted term its columns correlate with
// most (canonical correlation `correlation`), empty when none above 0.3.
struct ImplausibleEffect {
  Effect effect;
  std::string parameter;  // the parameter key out of range, e.g. "k" or "N"
  double value = 0.0;     // its largest |element|
  double bound = 0.0;     // the class's bound for it
  std::string sensor_class;
  std::optional<TermKey> absorbing;
  double correlation = 0.0;
  std::string reason;  // the sentence the report shows
};

struct ChannelRms {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // m/s^2
};

struct DiagnosisResult {
  std::string case_name;
  std::string simulation_kind;
  GridSpec grid;
  TimeOffsetEstimate time_offset_xcorr;
  std::vector<LocatedSpan> located;        // residual before modelling
  std::vector<Effect> effects;             // claimed
  std::vector<AmbiguousEffect> ambiguous;  // found, modelled, name not settled (not claimed)
  // Physics of the tested IMU that the simulation already carries beyond the linear model: the
  // lab fitting function's quadratic (scale_nonlinearity, k2 = c2 per axis, 1-sigma NaN on axes
  // fitted with a line), which SG#2 grafts, so the field residual cannot show it (evidence_method
  // "lab_degree_test"). Not claimed: it is not missing from the simulation. Left out for a sensor
  // whose scale_nonlinearity is claimed (its k2 includes the lab's c2) or whose residual cancels
  // the lab's c2 (then not the sensor's; see the notes).
  std::vector<Effect> in_simulation;
  // Every candidate left out of the final model, its parameters holding the detection limit
  // (each parameter alone, the others zero; about 50 % detection; term_selection.h TermLimit).
  std::vector<Effect> detection_limits;
  // Fitted but outside the tested IMU's plausible ranges: not claimed (claim_checks.h).
  std::vector<ImplausibleEffect> implausible;
  // Largest canonical correlation between every pair of fitted terms (term_correlation.h).
  std::vector<TermCorrelation> term_correlations;
  // When mounting rotation, non-orthogonality and scale were reported as one effect
  // (linear_response.h): the excitation their split would need.
  std::optional<SeparationNeed> separation;
  std::vector<QuantizationCheck> quantization_checks;  // per sensor, when detect_quantization
  std::optional<PlausibleRanges> plausible_ranges;     // the ranges the claims were checked with
  std::vector<LocatedSpan> unexplained;                // still above noise after modelling
  std::vector<WanderCheck> wander;  // per channel, when the lab's noise figures are known
  // Per bin: 1 = left out (overlaps a sampling gap of a record; common_grid.h), and those spans.
  std::vector<char> masked_bins;
  std::vector<std::pair<double, double>> masked_spans;  // [t_start, t_end) s
  ChannelRms rms_raw;                                   // residual as is
  ChannelRms rms_before;  // residual minus its per-channel constant + linear drift
  ChannelRms rms_after;   // residual minus constant, drift and selected terms
  bool has_holdout = false;
  ChannelRms holdout_before, holdout_after;  // second half, model fitted on the first half
  std::vector<TermKey> holdout_terms;        // terms selected on the first half
  double holdout_split_s = 0.0;
  Vector6d nuisance_bias = Vector6d::Zero();   // constant real - simulated per channel (SI)
  Vector6d nuisance_drift = Vector6d::Zero();  // linear drift over the record, end minus start (SI)
  SelectionResult selection;
  std::vector<std::string> notes;    // assumptions and warnings for the report
  Eigen::MatrixXd residual_before;   // n x 6, for plots
  Eigen::MatrixXd model;             // n x 6, selected terms (no constant)
  Eigen::MatrixXd nuisance;          // n x 6, constant + drift
  std::vector<std::string> regimes;  // per bin
  ImuSeries sg3;                     // simulated + selected terms (record mean removed)
  // SG#3 as passes when the simulation was a recording (DiagnosisInputs::simulated_recording):
  // each pass reads the simulation and adds the model block by block; `sg3` is then empty.
  std::optional<ImuRecording> sg3_recording;
};

// Works on a copy of the inputs; the overload below consumes them.
DiagnosisResult diagnose(const DiagnosisInputs& inputs, const DiagnoseOptions& options = {});
// The same result, holding less: the records are released as soon as the finder has binned them
// (the real record and, with remake_simulated, the simulation after the residual; the attitude
// after the regressors), so past binning only the reference record is held (docs/BENCHMARKS.md).
DiagnosisResult diagnose(DiagnosisInputs&& inputs, const DiagnoseOptions& options = {});

// The simulation used when the case has no lab data: the reference increments plus the tested
// IMU's bias measured in the first static span of the field recording (mean tested minus mean
// reference over that span, so the reference's own bias and the local gravity cancel). Throws
// std::runtime_error when no static span of at least min_static_s is found.
struct StaticBiasSimulation {
  ImuSeries simulated;
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();
  double t_start_s = 0.0, t_end_s = 0.0;
  // The tested IMU's mean temperature over the span, the simulation's temperature column (NaN
  // when the tested record has none).
  double temperature_degC = std::nan("");
};
StaticBiasSimulation simulateFromReferenceAndStaticBias(const ImuSeries& reference,
                                                        const ImuSeries& tested,
                                                        double min_static_s = 2.0,
                                                        double max_static_s = 30.0);

// The reference plus a constant bias per triad, every sample at one temperature (the static-bias
// simulation's series).
ImuSeries withStaticBias(const ImuSeries& reference, const Eigen::Vector3d& gyro_bias_rad_s,
                         const Eigen::Vector3d& accel_bias_m_s2, double temperature_degC);

// Step of a value lattice of the raw increments (rad or m/s per sample) per axis; 0 where the
// values are not on a lattice (fewer than half of them repeat, or they miss the lattice).
Eigen::Vector3d detectQuantizationStep(const ImuSeries& imu, Sensor sensor);
// The same from passes of a recording (one per axis).
Eigen::Vector3d detectQuantizationStep(const ImuRecording& imu, Sensor sensor);

// SG#3: the simulation plus a per-bin contribution (n x 6, SI rates) on `grid`, added to every
// sample as rate x dt from the bin that holds the sample's middle (clamped at the grid's ends).
ImuSeries addBinnedContribution(const ImuSeries& simulated, const GridSpec& grid,
                                const Eigen::MatrixXd& contribution);
// The same, in place.
void addBinnedContributionInPlace(const GridSpec& grid, const Eigen::MatrixXd& contribution,
                                  ImuSeries* series);
// The same as a recording: each pass of `simulated` with the contribution added block by block.
ImuRecording withBinnedContribution(ImuRecording simulated, const GridSpec& grid,
                                    Eigen::MatrixXd contribution);

}  // namespace graftnav
