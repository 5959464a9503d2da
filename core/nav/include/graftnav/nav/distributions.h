#pragma once
// Distribution functions used by the tests of significance across graftnav (NEES bands, the EKF's
// innovation gate, the mismatch finder's window test, the lab's fitting-function degree).

namespace graftnav {

// Quantile of the standard normal distribution.
double normalQuantile(double probability);

// Quantile of the chi-square distribution (bisection on the regularized incomplete gamma).
double chiSquareQuantile(double probability, double dof);

// Upper tail P(F > f) of Fisher's F distribution with (dof1, dof2) degrees of freedom, from the
// regularized incomplete beta function: P(F > f) = I_{dof2 / (dof2 + dof1 f)}(dof2 / 2, dof1 / 2).
// For dof2 > 1e7, the chi-square limit P(chi2(dof1) > dof1 f). Throws std::invalid_argument for
// dof <= 0; returns 1 for f <= 0.
double fisherUpperTail(double f, double dof1, double dof2);

}  // namespace graftnav
