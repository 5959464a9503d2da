#pragma once
// Mounting rotation, non-orthogonality and scale factor as one linear response.
//
// To first order each of them is a matrix acting on the true input: the residual of sensor s is
// r_s = E_s x_s with E_s = diag(k_s) + N_s - [phi x] (the rotation phi shared by both triads).
// A record identifies E_s only in the columns of x_s it excites. On a planar drive the gyros see
// omega ~ (0, 0, omega_z): E_gyro's x and y columns are not excited, so N_gyro,xz and phi_y (and
// N_gyro,yz and -phi_x) are one number each, and the accelerometers' f_z ~ -g column is a
// near-constant, one with the bias. Without a lab calibration that pins N and k, the split
// between the three terms is then set by the prior, not by the data: they are reported as one
// effect, E per sensor (fitted as that, beside the other claimed terms), with the excitation the
// split would need.
//
// Excitation needed: column j of E_s is determined to sigma_d,s / sqrt(integral x_j^2 dt), with
// sigma_d,s the residual's long-run noise density (the AR(1) innovation sigma / (1 - rho) times
// sqrt(bin_s) and the selection's variance inflation). The split is possible when that is at most
// a third of the class's non-orthogonality bound (plausible_ranges.h) for the gyro's roll- and
// pitch-rate columns; needed_s is the time at a stated RMS rate (gyro) or held at a stated tilt
// (accelerometer, g sin(tilt) on the column), present_s the record's own equivalent, times the
// share of its information the other members leave (1 - rho^2 of their largest canonical
// correlation). The noise is the residual's: a misfit of terms outside the library is taken as
// noise of that level, so the needed seconds are a lower bound.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/nav/units.h"

namespace graftnav {

struct LinearResponseOptions {
  double excitation_rate_rad_s = 30.0 * units::kDegToRad;  // RMS rate, gyro columns
  double excitation_tilt_rad = 30.0 * units::kDegToRad;    // held tilt, accel columns
  double resolve_fraction = 1.0 / 3.0;  // sigma at most this fraction of the bound
  void validate() const;
};

// What separating the terms would need, per input axis x, y (roll, pitch).
struct SeparationNeed {
  Eigen::Vector2d gyro_needed_s = Eigen::Vector2d::Zero();   // at excitation_rate_rad_s RMS
  Eigen::Vector2d gyro_present_s = Eigen::Vector2d::Zero();  // this record, same rate
  Eigen::Vector2d accel_needed_s = Eigen::Vector2d::Zero();  // held at excitation_tilt_rad
  double bound_rad = 0.0;                                    // the non-orthogonality bound used
  double rate_rad_s = 0.0, tilt_rad = 0.0;                   // the excitation options used
  bool separable = false;  // the record's roll and pitch excitation resolve the gyro columns
  double information_share = 1.0;  // of the present excitation, after shrinkPresent
  // A column correlated with the other members' keeps `share` of its information: the record's
  // equivalent seconds shrink alike, and separable is re-evaluated.
  void shrinkPresent(double share);
  std::string text() const;
};

// `reference` = the binned true inputs on the residual's grid (x.omega_rad_s, x.f_m_s2), `sel`
// the final selection (noise model), `bound_rad` the smaller non-orthogonality bound of the two
// triads. Throws std::invalid_argument for a non-positive bound or bin.
SeparationNeed separationNeed(const BinnedImu& reference, const SelectionResult& sel, double bin_s,
                              double bound_rad, const LinearResponseOptions& options = {});

// The candidate with E_gyro and E_accel as free parameters (18 columns, row-major per sensor:
// E_s(i, j) on channel i of sensor s, column x_s,j).
CandidateTerm linearResponseTerm(const BinnedImu& reference);

// Whether a term kind belongs to the linear response (mounting_misalignment,
// non_orthogonality, scale_factor).
bool isLinearResponseTerm(TermKind kind);

}  // namespace graftnav
