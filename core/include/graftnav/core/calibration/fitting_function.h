#pragma once
// Real-time fitting functions (seed Eq. 21): per axis a polynomial y = p(x) from the theoretical
// output x to the measured output y, coefficients lowest order first, degree chosen by k-fold
// cross-validation (not fixed).
//
// Points: for axis i every lab observation (pose or rate run) gives x = true_i and
// y = measured_i - sum_{j != i} M_ij true_j, i.e. the cross-axis part carried by the calibration
// matrix M is removed first (the grafting step adds it back from M), so p_i sees only its own
// axis. Fit: weighted least squares (weights 1/sigma^2); coefficient covariance
// (X^T W X)^-1 times max(1, reduced chi-square).
// Cross-validation: points sorted by x and dealt to `folds` folds in turn (deterministic;
// leave-one-out when there are at most 2 * folds points); score = mean squared whitened
// prediction error, every candidate degree on the same folds (those whose training set can fit
// the largest candidate); the chosen degree is the lowest whose score is within
// (1 + cv_tolerance) of the best. Candidate degrees go up to min(max_degree, points - 2,
// distinct x - 2): one spare support value, so six-position data (x = -g, 0, +g) gets a line, a
// rate table with several rates can get up to a cubic (x values closer than 1e-3 of the range
// count as one). cv_rms is NaN when no fold can be validated.

#include <array>
#include <string>
#include <vector>

#include "graftnav/core/calibration/calibration_result.h"
#include "graftnav/core/calibration/six_position.h"

namespace graftnav {

struct FitPoint {
  double x = 0.0, y = 0.0, sigma = 1.0;
};

struct PolynomialFitOptions {
  int max_degree = 3;       // <= 4
  int folds = 5;            // k of k-fold; capped at the number of points (leave-one-out)
  double cv_tolerance = 0.05;
  void validate() const;    // throws std::invalid_argument naming the field
};

// Weighted polynomial fit of a fixed degree (no cross-validation).
PolynomialFit fitPolynomial(const std::vector<FitPoint>& points, int degree);

// Cross-validated degree. Throws std::invalid_argument (naming `name`) with fewer than 3 points or
// fewer than 2 distinct x values.
PolynomialFit fitPolynomialCV(const std::vector<FitPoint>& points, const PolynomialFitOptions& options,
                              const std::string& name);

// Builds the per-axis points from observations and M (see above) and fits each axis.
std::array<PolynomialFit, 3> fitAxisPolynomials(const std::vector<LinearObservation>& obs,
                                                const Eigen::Matrix3d& M,
                                                const PolynomialFitOptions& options,
                                                const std::string& sensor_name);

}  // namespace graftnav
