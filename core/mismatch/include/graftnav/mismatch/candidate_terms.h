#pragma once
// The library of candidate physics terms the mismatch finder can use to explain the residual
// r = real - simulated (per bin, channels [gyro x, y, z (rad/s), accel x, y, z (m/s^2)]).
//
// Every term is linear in its parameters: r ~= sum_j theta_j u_j(t), where each regressor u_j is
// built from the reference signals x (the true inputs: omega, f), their derivatives, temperature,
// a vibration level or the attitude. What each term is (its regressor, sensors, parameters with
// units, plausible ranges) is its row in term_spec.h (src/terms/term_specs.cpp), and docs/mismatch.md
// shows those rows as a table; its builder (src/terms/) holds the physics of its columns. A
// constant bias per channel (optionally a linear drift too) is always in the model (turn-on bias
// differs between lab and field); it is a nuisance, not a claimed effect.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"

namespace graftnav {

constexpr int kMismatchChannels = 6;  // gyro x, y, z, accel x, y, z

// One regressor: its values on the channels it acts on (empty vector = 0 on that channel).
// A column over the whole grid holds every bin (first_row 0, grid_rows 0). A column that is
// non-zero on a few knot intervals only (bias_instability's hat functions) holds that stretch:
// channel[c](k) is bin first_row + k of a grid of grid_rows bins, zero outside it.
struct RegressorColumn {
  std::array<Eigen::VectorXd, kMismatchChannels> channel;
  int first_row = 0;
  int grid_rows = 0;  // 0: channel[c] holds every bin of the grid
  bool actsOn(int c) const { return channel[c].size() > 0; }
  // The bins of the grid and the end of the stored stretch on channel c.
  int gridRows(int c) const {
    return grid_rows > 0 ? grid_rows : static_cast<int>(channel[c].size());
  }
  int endRow(int c) const { return first_row + static_cast<int>(channel[c].size()); }
  // Bin i of channel c (zero outside the stored stretch).
  double at(int c, int i) const {
    const int k = i - first_row;
    return k >= 0 && k < channel[c].size() ? channel[c](k) : 0.0;
  }
  // Channel c over the whole grid (a copy).
  Eigen::VectorXd dense(int c) const;
};

// One term of the library: a TermSpec (term_spec.h) on a sensor scope, with its columns.
struct CandidateTerm {
  CandidateTerm() = default;
  // With the spec's required terms on the same scope (TermSpec::requires_kinds).
  CandidateTerm(const TermSpec& spec, SensorScope sensor, TermVariant variant = TermVariant::none);
  const TermSpec* spec = nullptr;
  SensorScope sensor = SensorScope::both;
  // vibration_rectification: the vibration level; the accelerometer's symmetric
  // non_orthogonality; the asymmetry replacing the lab quadratic; else none.
  TermVariant variant = TermVariant::none;
  std::string explanation;  // plain-language physics
  std::vector<RegressorColumn> columns;
  // Never selected on its own: only the selection's gauge step puts it in a final model (the
  // symmetric accelerometer non_orthogonality; term_selection.h, step 4).
  bool gauge_only = false;
  std::vector<TermKey> excludes;  // terms this one replaces when added
  // Terms that must be in the model when this one is tested (its evidence is measured against
  // the model with them) and that stay in it while this one does (a companion that fails its own
  // test is fitted but not claimed): the spec's requires_kinds, and a fixed part the term cannot
  // do without (mounting_rotation_remainder, lab_quadratic_replaced).
  std::vector<TermKey> requires_terms;
  // The term this fixed part completes (mounting_rotation_remainder: the rotation's remainder at
  // its pivot): in a model only with that term, never selected or claimed alone.
  std::optional<TermKey> part_of;
  double knot_spacing_s = 0.0;  // bias_instability only
  double t_ref_degC = 0.0;      // temperature terms only
  // The term's record mean is a physical offset from the simulation, not a part of the constant
  // bias it cannot be told from: temperature_bias regressed on the tested minus the simulation's
  // temperature is per_degC (T - T_sim), whose mean is the bias change between the temperature
  // behind the simulation's bias (the lab's) and the field's. SG#3 grafts such a term in full;
  // every other term only as its variation (stages/diagnosis_model.cpp).
  bool mean_is_physical = false;

  TermKind kind() const;
  const char* name() const;  // diagnosis.json's effect name
  bool nuisance() const;     // always in the model, never claimed
  bool fixed() const;        // coefficients fixed at 1 (earth_rotation_omitted, the parts)
  bool slow() const;         // TermSpec::slow
  TermKey key() const { return {spec, sensor, variant}; }
  // The sensor of a single-triad term (throws for a term on both).
  Sensor triad() const { return sensorOf(sensor); }
};

// What the regressors are built from, all on one grid.
struct RegressorInputs {
  BinnedImu reference;                      // true inputs x (reference IMU signals, binned)
  Eigen::MatrixXd time_offset_column;       // n x 6 (timeOffsetRegressor) or empty: no term
  Eigen::VectorXd tested_temperature_degC;  // n, or empty / NaN: no temperature terms
  // n, optional: the temperature behind the simulation's own bias (e.g. the tiled lab record of
  // SG#2, whose basic error signal carries the lab warm-up). When given, temperature_bias regresses
  // on T_tested - T_simulated: the simulation already holds p (T_simulated - T_ref).
  Eigen::VectorXd simulated_temperature_degC;
  // n x 3, optional: bin means of the angular acceleration (angularAccelerationPerBin); without
  // it the lever arm uses central differences of the bin means, which attenuate road
  // oscillations of a few Hz (~10 % at 2.5 Hz with 0.05-s bins) and so overstate r_m.
  Eigen::MatrixX3d omega_dot_rad_s2;
  // Optional (binEvenPowers, on the grid and shift of `reference`): bin means of |x| and x^2
  // per sample, the inputs of scale_asymmetry and scale_nonlinearity (empty: |bin mean| and
  // bin mean^2, exact without within-bin vibration).
  EvenPowerBins even_powers;
  Eigen::VectorXd vibration_f_hp_sq;  // n, specific_force_hp_sq level, or empty
  // n x 3, optional: the specific force the tested gyros feel, g_sensitivity's columns (the
  // reference's moved to the tested IMU by a fitted lever arm; empty: reference.f_m_s2).
  Eigen::MatrixX3d g_sensitivity_f_m_s2;
  Eigen::VectorXd vibration_w_hp_sq;  // n, angular_rate_hp_sq level, or empty
  // The tested IMU's accelerometer response as the lab calibrated it,
  // y_i = c0 + c1 x_i + c2_i x_i^2 + sum_j M_ij x_j: a motion signal the reference does not carry
  // (lever-arm acceleration, a mounting rotation's f x phi) reaches the tested output through its
  // slope J = M + diag(2 c2 f) at the bin's specific force. With f_z ~ -g a c2_z of 8e-4 per
  // m/s^2 scales the lever arm's z acceleration by -1.6 %. Identity / zero: no lab calibration.
  Eigen::Matrix3d accel_response_M = Eigen::Matrix3d::Identity();
  Eigen::Vector3d accel_response_c2 = Eigen::Vector3d::Zero();
  // The gyro's lab c2 (SG#2's quadratic per axis; zero: none). With accel_response_c2 it also
  // gives scale_asymmetry its alternative that replaces the lab quadratic (below).
  Eigen::Vector3d gyro_response_c2 = Eigen::Vector3d::Zero();
  // The rotation vector (rad) mounting_misalignment is linearized at. Zero: the first-order
  // columns x x phi. Non-zero (diagnose sets the rotation of a first pass): the columns are the
  // exact rotation's Jacobian there and a fixed part, mounting_rotation_remainder, carries the
  // rest, so a rotation of several degrees is not left with second-order "scale" terms.
  Eigen::Vector3d mounting_rotation_pivot_rad = Eigen::Vector3d::Zero();
  std::vector<Eigen::Matrix3d> C_bn;  // n attitudes (nav to body) or empty: no earth/gravity terms
  Eigen::Vector3d omega_ie_n = Eigen::Vector3d::Zero();  // Earth rate in n (rad/s)
};

// The built-in term specs (term_spec.h).
const std::vector<const TermSpec*>& builtInTermSpecs();

struct CandidateLibraryOptions {
  double knot_spacing_s = 60.0;  // bias_instability knot spacing (s)
  int max_knots = 20;            // the spacing grows for long records to keep at most this many
  double min_temperature_span_degC = 0.5;  // temperature terms need this much range
  // Add a linear drift per channel to the nuisance. Off by default: a drift absorbs most of a
  // temperature warm-up and costs the temperature terms their power.
  bool linear_drift_nuisance = false;
  // The term specs the library is built from (term_spec.h), the nuisance first: the built-in
  // rows, or those plus rows added outside them.
  std::vector<const TermSpec*> terms = builtInTermSpecs();
  void validate() const;
};

// Term 0 is the nuisance (constant bias per channel [+ linear drift], 6 [12] columns); the rest
// are the candidates whose inputs exist, built by the builders of options.terms in their groups'
// order (term_spec.h LibraryGroup).
std::vector<CandidateTerm> buildCandidateLibrary(const RegressorInputs& inputs,
                                                 const CandidateLibraryOptions& options = {});

// The per-bin level of a VibrationRegressor (imu_error_terms.h) run over the samples of `imu`,
// averaged over the samples whose end tag falls in each bin.
Eigen::VectorXd vibrationLevelPerBin(const ImuSeries& imu, const GridSpec& grid,
                                     const std::string& regressor_name, double window_s = 1.0);

// Bin means of the angular acceleration of `imu` on `grid`: (omega(b) - omega(a)) / (b - a) for
// bin (a, b] (exact for the instantaneous rate omega), omega at an edge from Richardson
// extrapolation of the mean rates over windows w and 2w centred on it, (4 m_w - m_2w) / 3 (gain
// error O((f w)^4): 0.2 % at 3.1 Hz, 1.2 % at 5 Hz for w = 0.05 s). Per axis, w is the shortest
// of h, h/2, h/4, ... (h = bin length, down to a quarter of the sample interval: the integral is
// band limited between samples) whose white noise in the regressor is at most
// `max_noise_fraction` of its variance: a short window follows road and engine vibration (a
// one-bin window's gain turns negative above 1/h = 20 Hz; at w = 1.25 dt 38 Hz of a 100-Hz
// record still lost 13 %), a long one keeps a noisy reference's noise out of the regressor
// (errors-in-variables biases r_m towards 0).
struct AngularAccelerationBins {
  Eigen::MatrixX3d omega_dot_rad_s2;    // n x 3
  Eigen::Vector3d window_s;             // the window w chosen per axis
  Eigen::Vector3d noise_fraction;       // white-noise share of the regressor's variance
  Eigen::Vector3d rate_noise_sd_rad_s;  // per-sample white noise of the rates (estimate)
};
// Throws std::invalid_argument with fewer than 2 samples.
AngularAccelerationBins angularAccelerationPerBin(const ImuSeries& imu, const GridSpec& grid,
                                                  double max_noise_fraction = 0.01);

// Contribution sum_j theta_j u_j of a term on the grid (n x 6). theta has one value per column
// (ignored for fixed terms, whose coefficients are 1).
Eigen::MatrixXd termContribution(const CandidateTerm& term, const Eigen::VectorXd& theta, int n);

}  // namespace graftnav
