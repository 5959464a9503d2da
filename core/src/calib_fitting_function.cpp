#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "graftnav/core/calibration/fitting_function.h"

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
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !(q.sigma > 0.0))
      throw std::invalid_argument("fitPolynomial: " + name + ": a point is not finite or has sigma <= 0");
}

}  // namespace

void PolynomialFitOptions::validate() const {
  if (max_degree < 1 || max_degree > 4)
    throw std::invalid_argument("PolynomialFitOptions: max_degree = " + std::to_string(max_degree) +
                                " must be in [1, 4]");
  if (folds < 2)
    throw std::invalid_argument("PolynomialFitOptions: folds = " + std::to_string(folds) + " must be >= 2");
  if (!(cv_tolerance >= 0.0))
    throw std::invalid_argument("PolynomialFitOptions: cv_tolerance must be >= 0");
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

PolynomialFit fitPolynomialCV(const std::vector<FitPoint>& pts_in, const PolynomialFitOptions& opt,
                              const std::string& name) {
  opt.validate();
  checkPoints(pts_in, name);
  if (pts_in.size() < 3 || distinctX(pts_in) < 2)
    throw std::invalid_argument("fitPolynomialCV: " + name + ": need >= 3 points with >= 2 distinct x, got " +
                                std::to_string(pts_in.size()) + " points");
  std::vector<FitPoint> pts = pts_in;
  std::stable_sort(pts.begin(), pts.end(), [](const FitPoint& a, const FitPoint& b) { return a.x < b.x; });
  const int n = static_cast<int>(pts.size());
  // Few points: leave-one-out (k-fold with 2-point folds can leave a training set without spread).
  const int folds = n <= 2 * opt.folds ? n : opt.folds;
  std::vector<std::vector<FitPoint>> train(folds), test(folds);
  for (int i = 0; i < n; ++i)
    for (int f = 0; f < folds; ++f) (i % folds == f ? test[f] : train[f]).push_back(pts[i]);
  // Candidate degrees: at most min(max_degree, points - 2, distinct x - 2), i.e. at least one
  // spare support value, so the polynomial never just interpolates the cluster means. All
  // candidates are scored on the same folds: those whose training set can fit the largest
  // candidate; when these cover less than half of the points the largest candidate is dropped.
  const double range = xRange(pts);
  int max_deg = std::max(1, std::min(opt.max_degree, std::min(n - 2, distinctX(pts) - 2)));
  std::vector<int> use;
  for (; max_deg >= 1; --max_deg) {
    use.clear();
    int covered = 0;
    for (int f = 0; f < folds; ++f)
      if (distinctX(train[f], range) >= max_deg + 1 && static_cast<int>(train[f].size()) >= max_deg + 2) {
        use.push_back(f);
        covered += static_cast<int>(test[f].size());
      }
    if (covered * 2 >= n || max_deg == 1) break;
  }
  std::vector<double> score(max_deg + 1, INFINITY), mse(max_deg + 1, NAN);
  for (int d = 1; d <= max_deg; ++d) {
    double s = 0.0, m = 0.0;
    int cnt = 0;
    for (int f : use) {
      const WeightedLsq w = solve(train[f], d);
      for (const auto& q : test[f]) {
        double y = 0.0, v = 1.0;
        for (int k = 0; k <= d; ++k, v *= q.x) y += w.coeffs[k] * v;
        s += std::pow((q.y - y) / q.sigma, 2);
        m += std::pow(q.y - y, 2);
        ++cnt;
      }
    }
    if (cnt > 0) {
      score[d] = s / cnt;
      mse[d] = m / cnt;
    }
  }
  double best = INFINITY;
  for (int d = 1; d <= max_deg; ++d) best = std::min(best, score[d]);
  int chosen = 1;
  for (int d = 1; d <= max_deg; ++d)
    if (std::isfinite(score[d]) && score[d] <= best * (1.0 + opt.cv_tolerance)) {
      chosen = d;
      break;
    }
  PolynomialFit fit = fitPolynomial(pts, chosen);
  fit.cv_rms = std::sqrt(mse[chosen]);  // NaN when no fold could validate (e.g. 2 distinct x)
  return fit;
}

std::array<PolynomialFit, 3> fitAxisPolynomials(const std::vector<LinearObservation>& obs,
                                                const Eigen::Matrix3d& M,
                                                const PolynomialFitOptions& options,
                                                const std::string& sensor) {
  std::array<PolynomialFit, 3> out;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    std::vector<FitPoint> pts;
    for (const auto& o : obs) {
      double y = o.measured[i];
      for (int j = 0; j < 3; ++j)
        if (j != i) y -= M(i, j) * o.true_value[j];
      pts.push_back({o.true_value[i], y, o.sigma[i]});
    }
    out[i] = fitPolynomialCV(pts, options, sensor + "." + axes[i]);
  }
  return out;
}

}  // namespace graftnav
