#pragma once
// Joint non-linear fit of the time offset and the selected terms with Ceres.
// The linear selection (term_selection.h) treats the time offset through a regressor
// linearised at a pivot; here tau_s is a genuinely non-linear parameter of a ceres::Problem:
//
//   r(t) = [X_tau(t) - X(t)] + K(t) - tau K'(t) + sum_j theta_j (u_j(t) - tau u_j'(t)) + e(t)
//
//   X_tau   bin means of the reference signal shifted by tau, from its cumulative integral
//           (exact for any tau: bin (a, b] takes (Theta(b - tau) - Theta(a - tau)) / (b - a));
//           its derivative in tau uses the sample rates at b - tau and a - tau;
//   u_j     the regressor columns of the other model terms (nuisance included), so the shift of
//           their contribution is modelled to first order (u' = central difference per bin);
//   K       the contribution of fixed terms (coefficient 1), shifted the same way.
// When the regressors were built from the reference already shifted by a pivot p (x(t - p), as
// diagnose does), their first-order shift is (tau - p) instead of tau: u_j - (tau - p) u_j'.
// The residual e is AR(1)-whitened per channel with the linear fit's rho_c and sigma_c (the same
// prewhitening as the selection), and the parameter covariance comes from ceres::Covariance
// (dense SVD, rank-revealing), multiplied by the selection's AR(1) inflation c and each term's
// slow-noise factor (TermFit::inflation_factor) exactly as the linear covariance is.
// The linear solution initialises the solver. diagnose reports the joint fit's tau; once the
// selection ran at that tau as its pivot (where the linear model is exact), the other terms keep
// the selection's GLS estimates, which weigh slow noise per time scale as this fit does not.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct JointFitOptions {
  int max_iterations = 50;                  // Levenberg-Marquardt iterations
  int chunk_bins = 256;                     // bins per Ceres residual block
  double min_reciprocal_condition = 1e-14;  // dense-SVD covariance truncation
  void validate() const;                    // throws std::invalid_argument naming the field
};

struct JointFitResult {
  bool converged = false;  // Ceres reported convergence and the covariance was computed
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;  // 0.5 x whitened sum of squares
  double tau_s = 0.0;
  double tau_sigma_s = 0.0;    // inflated like the linear covariance
  TermFit nuisance;            // constant bias per channel
  std::vector<TermFit> terms;  // the linear fit's selected terms, in its order; the time_offset
                               // term carries theta = [tau_s]
  // n x 6 prediction of the joint model without the nuisance (the shift of the reference, the
  // shifted other terms and the fixed terms): what the finder subtracts and grafts (SG#3).
  Eigen::MatrixXd model;
  std::string summary;  // one line: costs, iterations, tau linear -> joint
};

// Fits `linear`'s model (nuisance + selected terms) with the time offset of term
// `time_offset_term` (index into `terms`) as a non-linear parameter. `residual` is n x 6 on
// `grid` (real minus simulated), `reference` the reference IMU record. Evidence (delta_bic,
// cv_gain, claimed) is copied from `linear`. `regressor_pivot_s`: the shift p the other terms'
// regressors were built at (0 when from the unshifted reference). Throws std::invalid_argument
// when the sizes do not match or the time_offset term is not in `linear.selected`.
JointFitResult jointFitWithTimeOffset(const Eigen::MatrixXd& residual, const ImuSeries& reference,
                                      const GridSpec& grid, const std::vector<CandidateTerm>& terms,
                                      const SelectionResult& linear, int time_offset_term,
                                      double regressor_pivot_s = 0.0,
                                      const JointFitOptions& options = {},
                                      const ImuSampleMap& response = {});

}  // namespace graftnav
