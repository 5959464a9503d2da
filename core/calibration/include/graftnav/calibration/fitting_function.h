#pragma once
// Real-time fitting functions (seed Eq. 21): per axis a polynomial y = p(x) from the theoretical
// output x to the measured output y, coefficients lowest order first, degree chosen by a test of
// significance (not fixed).
//
// Points: for axis i every lab observation (pose or rate run) gives x = true_i and
// y = measured_i - sum_{j != i} M_ij true_j, i.e. the cross-axis part carried by the calibration
// matrix M is removed first (the grafting step adds it back from M), so p_i sees only its own
// axis. Fit: weighted least squares (weights 1/sigma^2); coefficient covariance
// (X^T W X)^-1 times max(1, reduced chi-square).
// Point sigmas: the pose's sigma-of-mean (white noise) and, in quadrature, the drift of a pose
// mean against the session's other poses (pose_drift.h) when the lab has a static record.
// Point sigmas with an estimated part: FitPoint::sigma_dof; fitAxisPolynomials gives each point
// (s^2 + d^2)^2 / (d^4 / dof_d) for white sigma s and drift d known to dof_d.
// Degree: candidates go up to min(max_degree, points - 2, distinct x - 2): one spare support
// value, so six-position data (x = -g, 0, +g) gets a line, a tilt pose adds a quadratic, a rate
// table with several rates can get up to a cubic (x values closer than 1e-3 of the range count as
// one). From the largest candidate down, the top coefficient of degree d is dropped while the
// chi-square drop it buys, chi2_{d-1} - chi2_d, is not significant at degree_alpha: against
// chi2(1) when the residuals scatter no more than the sigmas say (chi2_d / (n - d - 1) <= 1) and
// the sigmas are known; against F(1, nu + n - d - 1) when they are estimated (nu the smallest
// sigma_dof: the sigmas' scale is then known to nu degrees of freedom from its estimate and
// n - d - 1 from the residuals; the drop is not rescaled by the residuals' smaller scatter, which
// keeps the test conservative; nu > 1e7 counts as known); otherwise by the nested F-test
// F = (chi2_{d-1} - chi2_d) / (chi2_d / (n - d - 1)), which scales by the scatter the sigmas
// leave out. Leave-one-out cross-validation, used before, missed a
// 2.4-mg accelerometer quadratic (docs/calibration.md): with one point at each end of the range,
// leaving it out makes every quadratic an extrapolation.
// cv_rms: k-fold (leave-one-out for at most 2 * folds points) prediction RMS of the chosen degree,
// reported only; NaN when no fold's training set can fit it.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "graftnav/calibration/calibration_result.h"
#include "graftnav/calibration/pose_drift.h"
#include "graftnav/calibration/six_position.h"

namespace graftnav {

struct FitPoint {
  double x = 0.0, y = 0.0, sigma = 1.0;
  double sigma_dof =
      INFINITY;  // degrees of freedom of sigma^2 when it is estimated (Satterthwaite)
};

struct PolynomialFitOptions {
  int max_degree = 3;  // <= 4
  int folds = 5;       // k of k-fold for cv_rms; leave-one-out for at most 2 * folds points
  // False-alarm probability of a degree step, in (0, 1): of one axis in fitPolynomialSelectDegree,
  // of the sensor (any of its three axes, Sidak 1 - (1 - alpha)^(1/3) per axis) in
  // fitAxisPolynomials.
  double degree_alpha = 0.01;
  void validate() const;  // throws std::invalid_argument naming the field
  double perAxisAlpha() const { return 1.0 - std::pow(1.0 - degree_alpha, 1.0 / 3.0); }
};

// Weighted polynomial fit of a fixed degree (no cross-validation).
PolynomialFit fitPolynomial(const std::vector<FitPoint>& points, int degree);

// Degree by the backward F-test (above). Throws std::invalid_argument (naming `name`) with fewer
// than 3 points or fewer than 2 distinct x values.
PolynomialFit fitPolynomialSelectDegree(const std::vector<FitPoint>& points,
                                        const PolynomialFitOptions& options,
                                        const std::string& name);

// Builds the per-axis points from observations and M (see above) and fits each axis;
// pose_drift.sigma (per axis, the unit of the observations) is added to every point's sigma in
// quadrature, with its degrees of freedom carried into sigma_dof. degree_alpha holds for the
// sensor: a false curvature on any axis becomes a difference between SG#2 and the real IMU (at
// 1 % per axis, 2 of 75 common-random-numbers runs had a lab-made accel quadratic claimed by the
// mismatch finder as a scale factor; docs/calibration.md).
std::array<PolynomialFit, 3> fitAxisPolynomials(const std::vector<LinearObservation>& obs,
                                                const Eigen::Matrix3d& M,
                                                const PolynomialFitOptions& options,
                                                const std::string& sensor_name,
                                                const PoseDriftEstimate& pose_drift = {});

}  // namespace graftnav
