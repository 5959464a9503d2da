#include "graftnav/nav/distributions.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {

double normalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) {
    throw std::invalid_argument("normalQuantile: probability must be in (0,1), got " +
                                std::to_string(p));
  }
  // Rational approximation (Acklam), |relative error| < 1.2e-9 after one Newton step below.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double plow = 0.02425;
  double x;
  if (p < plow) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - plow) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  // One Newton refinement on the CDF.
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2.0 * M_PI) * std::exp(x * x / 2.0);
  return x - u / (1.0 + x * u / 2.0);
}

namespace {

// Regularized lower incomplete gamma P(a, x): series for x < a + 1, continued fraction otherwise.
double regularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return sum * std::exp(log_prefix);
  }
  // Lentz's continued fraction for Q(a, x).
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double chiSquareQuantile(double p, double dof) {
  if (!(dof > 0.0)) {
    throw std::invalid_argument("chiSquareQuantile: dof must be > 0, got " + std::to_string(dof));
  }
  // Wilson-Hilferty start, then bisection on the exact CDF P(dof/2, x/2).
  const double z = normalQuantile(p);
  const double h = 2.0 / (9.0 * dof);
  const double t = 1.0 - h + z * std::sqrt(h);
  const double x0 = dof * std::max(1e-3, t * t * t);
  double lo = 0.0, hi = std::max(2.0 * x0, dof + 20.0 * std::sqrt(2.0 * dof) + 50.0);
  for (int i = 0; i < 200 && hi - lo > 1e-10 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (regularizedGammaP(0.5 * dof, 0.5 * mid) < p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

// Continued fraction of the regularized incomplete beta (modified Lentz); converges quickly for
// x < (a + 1) / (a + b + 2), the caller uses the symmetry I_x(a, b) = 1 - I_{1-x}(b, a) otherwise.
double incompleteBetaFraction(double a, double b, double x) {
  const double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m < 1000; ++m) {
    const double m2 = 2.0 * m;
    double num = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));  // even step
    d = 1.0 + num * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + num / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    h *= d * c;
    num = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));  // odd step
    d = 1.0 + num * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + num / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return h;
}

double regularizedBeta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0))
    return std::exp(log_front) * incompleteBetaFraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * incompleteBetaFraction(b, a, 1.0 - x) / b;
}

}  // namespace

double fisherUpperTail(double f, double dof1, double dof2) {
  if (!(dof1 > 0.0) || !(dof2 > 0.0)) {
    throw std::invalid_argument("fisherUpperTail: degrees of freedom must be > 0, got " +
                                std::to_string(dof1) + ", " + std::to_string(dof2));
  }
  if (!(f > 0.0)) return 1.0;
  // dof1 F tends to chi2(dof1) as dof2 grows; beyond 1e7 the incomplete beta's argument
  // dof2 / (dof2 + dof1 f) rounds towards 1 and its tail loses its digits.
  if (dof2 > 1e7) return std::isinf(f) ? 0.0 : 1.0 - regularizedGammaP(0.5 * dof1, 0.5 * dof1 * f);
  return regularizedBeta(0.5 * dof2, 0.5 * dof1, dof2 / (dof2 + dof1 * f));
}

}  // namespace graftnav
