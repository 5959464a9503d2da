#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "graftnav/calibration/fitting_function.h"
#include "graftnav/nav/distributions.h"

namespace graftnav {
namespace {

// Number of distinct x values, values closer than 1e-3 of the x range counting as one (static
// poses differ only by the Earth rate and must not pass for separate support points).
double xRange(const std::vector<FitPoint>& pts) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : pts) {
    lo = std::min(lo, p.x);
    hi = std::max(hi, p.x);
  }
  return pts.empty() ? 0.0 : hi - lo;
}

int distinctX(const std::vector<FitPoint>& pts, double range = -1.0) {
  if (pts.empty()) return 0;
  std::vector<double> xs;
  for (const auto& p : pts) xs.push_back(p.x);
  std::sort(xs.begin(), xs.end());
  const double tol = 1e-3 * (range >= 0.0 ? range : xs.back() - xs.front());
  int n = 1;
  for (std::size_t i = 1; i < xs.size(); ++i)
    if (xs[i] - xs[i - 1] > tol) ++n;
  return n;
}

// Column scaling keeps the Vandermonde system well conditioned for x of any unit.
struct WeightedLsq {
  Eigen::VectorXd coeffs;
  Eigen::MatrixXd cov;  // unscaled (X^T W X)^-1
  double chi2 = 0.0;
};

WeightedLsq solve(const std::vector<FitPoint>& pts, int degree) {
  const int n = static_cast<int>(pts.size()), p = degree + 1;
  double xs = 0.0;
  for (const auto& q : pts) xs = std::max(xs, std::abs(q.x));
  if (xs == 0.0) xs = 1.0;
  Eigen::MatrixXd X(n, p);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    const double w = 1.0 / pts[i].sigma;
    double v = 1.0;
    for (int k = 0; k < p; ++k, v *= pts[i].x / xs) X(i, k) = v * w;
    y[i] = pts[i].y * w;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  WeightedLsq out;
  Eigen::VectorXd c = qr.solve(y);
  out.chi2 = (X * c - y).squaredNorm();
  Eigen::MatrixXd cov = (X.transpose() * X).inverse();
  Eigen::VectorXd unscale(p);
  double s = 1.0;
  for (int k = 0; k < p; ++k, s /= xs) unscale[k] = s;
  out.coeffs = c.cwiseProduct(unscale);
  out.cov = unscale.asDiagonal() * cov * unscale.asDiagonal();
  return out;
}

void checkPoints(const std::vector<FitPoint>& pts, const std::string& name) {
  for (const auto& q : pts)
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !(q.sigma > 0.0) || !(q.sigma_dof > 0.0))
      throw std::invalid_argument("fitPolynomial: " + name +
                                  ": a point is not finite or has sigma <= 0 or sigma_dof <= 0");
}

// p-value of the top coefficient of degree d: when the residuals scatter no more than the point
// sigmas say (reduced chi-square <= 1), the chi-square drop it buys against F(1, sigma_dof + dof),
// the sigmas' scale being estimated to sigma_dof degrees of freedom; for known sigmas
// (sigma_dof infinite) that is chi2(1), fisherUpperTail's limit. Conservative: the drop is not
// rescaled by the residuals' smaller scatter, for which F(1, sigma_dof + dof) is the exact
// reference of the pooled statistic. Otherwise the nested F-test, which scales by the scatter
// left at degree d.
double degreeStepPValue(double chi2_lower, double chi2_d, int dof, double sigma_dof) {
  const double drop = std::max(0.0, chi2_lower - chi2_d);
  const double reduced = chi2_d / dof;
  if (reduced > 1.0) return fisherUpperTail(drop / reduced, 1.0, dof);
  return fisherUpperTail(drop, 1.0, sigma_dof + dof);
}

}  // namespace

void PolynomialFitOptions::validate() const {
  if (max_degree < 1 || max_degree > 4)
    throw std::invalid_argument("PolynomialFitOptions: max_degree = " + std::to_string(max_degree) +
                                " must be in [1, 4]");
  if (folds < 2)
    throw std::invalid_argument("PolynomialFitOptions: folds = " + std::to_string(folds) +
                                " must be >= 2");
  if (!(degree_alpha > 0.0 && degree_alpha < 1.0))
    throw std::invalid_argument("PolynomialFitOptions: degree_alpha = " +
                                std::to_string(degree_alpha) + " must be in (0, 1)");
}

PolynomialFit fitPolynomial(const std::vector<FitPoint>& pts, int degree) {
  checkPoints(pts, "fixed degree");
  if (degree < 0 || static_cast<int>(pts.size()) < degree + 1 || distinctX(pts) < degree + 1)
    throw std::invalid_argument("fitPolynomial: degree " + std::to_string(degree) + " needs " +
                                std::to_string(degree + 1) + " distinct x values");
  const WeightedLsq s = solve(pts, degree);
  const int dof = static_cast<int>(pts.size()) - (degree + 1);
  const double scale = dof > 0 ? std::max(1.0, s.chi2 / dof) : 1.0;
  PolynomialFit f;
  f.degree = degree;
  f.n_points = static_cast<int>(pts.size());
  double ss = 0.0;
  for (int k = 0; k <= degree; ++k) {
    f.coeffs.push_back(s.coeffs[k]);
    f.coeffs_sigma.push_back(std::sqrt(s.cov(k, k) * scale));
  }
  for (const auto& q : pts) ss += std::pow(q.y - f.evaluate(q.x), 2);
  f.residual_rms = std::sqrt(ss / pts.size());
  return f;
}

PolynomialFit fitPolynomialSelectDegree(const std::vector<FitPoint>& pts_in,
                                        const PolynomialFitOptions& opt, const std::string& name) {
  opt.validate();
  checkPoints(pts_in, name);
  if (pts_in.size() < 3 || distinctX(pts_in) < 2)
    throw std::invalid_argument("fitPolynomialSelectDegree: " + name +
                                ": need >= 3 points with >= 2 distinct x, got " +
                                std::to_string(pts_in.size()) + " points");
  std::vector<FitPoint> pts = pts_in;
  std::stable_sort(pts.begin(), pts.end(),
                   [](const FitPoint& a, const FitPoint& b) { return a.x < b.x; });
  const int n = static_cast<int>(pts.size());
  // Candidate degrees: at most min(max_degree, points - 2, distinct x - 2), i.e. at least one
  // spare support value, so the polynomial never just interpolates the cluster means.
  const int max_deg = std::max(1, std::min(opt.max_degree, std::min(n - 2, distinctX(pts) - 2)));
  // Backward elimination: the top coefficient of degree d stays when the drop in weighted
  // chi-square it buys is significant at `degree_alpha` (degreeStepPValue).
  int chosen = max_deg;
  double sigma_dof = INFINITY;
  for (const auto& q : pts) sigma_dof = std::min(sigma_dof, q.sigma_dof);
  std::vector<double> chi2(max_deg + 1, 0.0);
  for (int d = 1; d <= max_deg; ++d) chi2[d] = solve(pts, d).chi2;
  for (; chosen > 1; --chosen) {
    const int dof = n - chosen - 1;
    if (degreeStepPValue(chi2[chosen - 1], chi2[chosen], dof, sigma_dof) < opt.degree_alpha) break;
  }
  PolynomialFit fit = fitPolynomial(pts, chosen);
  if (max_deg >= 2) {
    const PolynomialFit quadratic = chosen == 2 ? fit : fitPolynomial(pts, 2);
    fit.c2_tested = quadratic.coeffs[2];
    fit.c2_tested_sigma = quadratic.coeffs_sigma[2];
  }
  // The fit's response to the shapes it leaves out: the same solve with y = |x| and y = x^2.
  std::vector<FitPoint> abs_pts = pts, sq_pts = pts;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    abs_pts[i].y = std::abs(pts[i].x);
    sq_pts[i].y = pts[i].x * pts[i].x;
  }
  if (chosen <= 2) {
    fit.slope_per_abs = solve(abs_pts, chosen).coeffs[1];
    fit.slope_per_sq = chosen == 1 ? solve(sq_pts, 1).coeffs[1] : 0.0;
  }
  if (max_deg >= 2) fit.c2_tested_per_abs = solve(abs_pts, 2).coeffs[2];
  // Cross-validated prediction RMS of the chosen degree, reported only (NaN when no fold's
  // training set can fit it). Points sorted by x and dealt to the folds in turn; leave-one-out
  // with few points (2-point folds can leave a training set without spread).
  const int folds = n <= 2 * opt.folds ? n : opt.folds;
  const double range = xRange(pts);
  double ss = 0.0;
  int cnt = 0;
  for (int f = 0; f < folds; ++f) {
    std::vector<FitPoint> train, test;
    for (int i = 0; i < n; ++i) (i % folds == f ? test : train).push_back(pts[i]);
    if (distinctX(train, range) < chosen + 1 || static_cast<int>(train.size()) < chosen + 2)
      continue;
    const WeightedLsq w = solve(train, chosen);
    for (const auto& q : test) {
      double y = 0.0, v = 1.0;
      for (int k = 0; k <= chosen; ++k, v *= q.x) y += w.coeffs[k] * v;
      ss += std::pow(q.y - y, 2);
      ++cnt;
    }
  }
  fit.cv_rms = cnt > 0 ? std::sqrt(ss / cnt) : NAN;
  return fit;
}

std::array<PolynomialFit, 3> fitAxisPolynomials(const std::vector<LinearObservation>& obs,
                                                const Eigen::Matrix3d& M,
                                                const PolynomialFitOptions& options,
                                                const std::string& sensor,
                                                const PoseDriftEstimate& pose_drift) {
  std::array<PolynomialFit, 3> out;
  const char* axes[3] = {"x", "y", "z"};
  options.validate();
  PolynomialFitOptions per_axis = options;
  per_axis.degree_alpha = options.perAxisAlpha();
  for (int i = 0; i < 3; ++i) {
    std::vector<FitPoint> pts;
    for (const auto& o : obs) {
      double y = o.measured[i];
      for (int j = 0; j < 3; ++j)
        if (j != i) y -= M(i, j) * o.true_value[j];
      const double drift2 = pose_drift.sigma[i] * pose_drift.sigma[i];
      const double var = o.sigma[i] * o.sigma[i] + drift2;
      const double dof = drift2 > 0.0 && std::isfinite(pose_drift.dof[i])
                             ? var * var / (drift2 * drift2 / pose_drift.dof[i])
                             : INFINITY;
      pts.push_back({o.true_value[i], y, std::sqrt(var), dof});
    }
    out[i] = fitPolynomialSelectDegree(pts, per_axis, sensor + "." + axes[i]);
  }
  return out;
}

}  // namespace graftnav
