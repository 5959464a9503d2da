// weighOneSignedSlope (mismatch/gain_or_curvature.h): the chi-squares, the combined k2 and the
// asymmetry's two-parameter estimate against hand-computed values, the verdict following the
// lab's degree-2 coefficient, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/mismatch/gain_or_curvature.h"

namespace graftnav {
namespace {

OneSignedSlopeInputs lineKept(double k, double k_sigma, double x_mean, double c2, double c2_sigma) {
  OneSignedSlopeInputs in;
  in.k = k;
  in.k_sigma = k_sigma;
  in.x_mean = x_mean;
  in.c2_lab = c2;
  in.c2_lab_sigma = c2_sigma;
  return in;
}

TEST(GainOrCurvature, MarginAndCombinedCurvatureByHand) {
  // Field: k = 1.2e-3 +- 2e-4 at x_mean = -10 -> k2_field = -6e-5 +- 1e-5.
  // Lab: -5e-5 +- 2e-5. chi2_gain = 6.25; chi2_curvature = (1e-5)^2 / 5e-10 = 0.2.
  const OneSignedSlope w = weighOneSignedSlope(lineKept(1.2e-3, 2e-4, -10.0, -5e-5, 2e-5));
  EXPECT_NEAR(w.k2_field, -6e-5, 1e-18);
  EXPECT_NEAR(w.k2_field_sigma, 1e-5, 1e-18);
  EXPECT_NEAR(w.chi2_gain, 6.25, 1e-9);
  EXPECT_NEAR(w.chi2_curvature, 0.2, 1e-9);
  EXPECT_TRUE(std::isnan(w.chi2_asymmetry)) << "no lab responses: the asymmetry is not weighed";
  EXPECT_EQ(w.best, SlopeCause::kCurvature);
  EXPECT_EQ(w.runner_up, SlopeCause::kGain);
  EXPECT_NEAR(w.margin, 6.25 - 0.2, 1e-9);
  // Inverse-variance mean: (-5e-5 / 4e-10 + -6e-5 / 1e-10) / (2.5e9 + 1e10) = -5.8e-5.
  EXPECT_NEAR(w.k2, -5.8e-5, 1e-15);
  EXPECT_NEAR(w.k2_sigma, std::sqrt(1.0 / 1.25e10), 1e-15);
}

TEST(GainOrCurvature, LabWithoutCurvatureSpeaksForAGain) {
  // The same field gain with a lab that sees no curvature (0 +- 1e-5): the gain changed.
  const OneSignedSlope gain = weighOneSignedSlope(lineKept(1.2e-3, 2e-4, -10.0, 0.0, 1e-5));
  EXPECT_EQ(gain.best, SlopeCause::kGain);
  EXPECT_GT(gain.margin, 6.0);
  // A lab too coarse to tell (0 +- 2e-4): neither side has evidence.
  const OneSignedSlope coarse = weighOneSignedSlope(lineKept(1.2e-3, 2e-4, -10.0, 0.0, 2e-4));
  EXPECT_EQ(coarse.best, SlopeCause::kGain);
  EXPECT_LT(coarse.margin, 1.0);
}

// Six-position responses (slope_per_abs 0, c2_tested_per_abs 1 / g) at x_mean = -g: an asymmetry
// d leaves the field slope z1 = -d (sign -1) and the lab coefficient z2 = d / g; a curvature k2
// gives z1 = -2 g k2, z2 = k2. The lab kept a line.
TEST(GainOrCurvature, AsymmetryFoldedIntoTheLabsQuadraticByHand) {
  const double g = 10.0, d = 2e-3;
  OneSignedSlopeInputs in = lineKept(-d, 1e-4, -g, d / g + 1e-6, 2e-5);
  in.slope_per_abs = 0.0;
  in.c2_per_abs = 1.0 / g;
  const OneSignedSlope w = weighOneSignedSlope(in);
  // d from the field 2e-3 +- 1e-4, from the lab 2.01e-3 +- 2e-4: chi2 = 1e-10 / 5e-8 = 2e-3.
  EXPECT_NEAR(w.chi2_asymmetry, 1e-10 / 5e-8, 1e-9);
  EXPECT_NEAR(w.chi2_gain, std::pow(2.01e-4 / 2e-5, 2), 1e-6);
  // Curvature: k2_field = -d / (-2 g) = 1e-4 +- 5e-6 against 2.01e-4 +- 2e-5.
  EXPECT_NEAR(w.chi2_curvature, std::pow(1.01e-4, 2) / (4e-10 + 2.5e-11), 1e-6);
  EXPECT_EQ(w.best, SlopeCause::kAsymmetry);
  EXPECT_GT(w.margin, 6.0);
  // Two parameters: D = -1 - (-2 g)(1 / g) = 1; d = z1 - Bk z2 = -2e-3 + 20 (2.01e-4) = 2.02e-3,
  // sigma sqrt(1e-8 + 400 x 4e-10) = 1.3e-4; k2 beside it = z2 - d / g = -1e-6.
  EXPECT_NEAR(w.d, 2.02e-3, 1e-12);
  EXPECT_NEAR(w.d_sigma, std::sqrt(1e-8 + 400.0 * 4e-10), 1e-12);
  EXPECT_NEAR(w.k2_beside_d, -1e-6, 1e-12);
  // k2 = z2 (1 + c2_per_abs Bk / D) - (c2_per_abs / D) z1 = -z2 - z1 / g:
  // sigma sqrt(4e-10 + 1e-2 x 1e-8).
  EXPECT_NEAR(w.k2_beside_d_sigma, std::sqrt(4e-10 + 1e-10), 1e-15);
  EXPECT_TRUE(w.d_with_curvature);
}

// Where the asymmetry's column (lab and field) is proportional to the curvature's (x_mean =
// -g / 2 with six-position responses: D = 0), the two are one hypothesis: equal chi-square, and
// d comes from the one-parameter fit.
TEST(GainOrCurvature, AsymmetryProportionalToTheCurvatureIsNotTold) {
  const double g = 10.0;
  OneSignedSlopeInputs in = lineKept(1e-3, 1e-4, -0.5 * g, 1e-4, 2e-5);
  in.slope_per_abs = 0.0;
  in.c2_per_abs = 1.0 / g;
  const OneSignedSlope w = weighOneSignedSlope(in);
  ASSERT_TRUE(std::isfinite(w.chi2_asymmetry)) << "weighed, not dropped";
  EXPECT_NEAR(w.chi2_asymmetry, w.chi2_curvature, 1e-9);
  EXPECT_FALSE(w.d_with_curvature);
  EXPECT_TRUE(std::isfinite(w.d));
  EXPECT_NEAR(w.margin, 0.0, 1e-9) << "the two lead together";
}

// The lab kept a quadratic that is a real curvature (SG#2 grafts it) and the field gain changed:
// no one-parameter cause fits both, and the two-parameter ones fit alike: unsettled.
TEST(GainOrCurvature, RealCurvatureAndAGainChangeAreUnsettled) {
  const double g = 10.0, c2 = -2e-4, k_g = 3e-3;
  OneSignedSlopeInputs in = lineKept(k_g, 1e-4, -g, c2, 1e-5);
  in.c2_simulated = c2;  // the residual slope is relative to SG#2's quadratic
  in.slope_per_abs = 0.0;
  in.c2_per_abs = 1.0 / g;
  const OneSignedSlope w = weighOneSignedSlope(in);
  EXPECT_GT(w.chi2_gain, 9.0);
  EXPECT_GT(w.chi2_curvature, 9.0);
  EXPECT_GT(w.chi2_asymmetry, 9.0);
  EXPECT_EQ(w.best, SlopeCause::kUnsettled);
  EXPECT_EQ(w.margin, 0.0);
  // Without the gain change, a field slope of the lab's c2 being off by 1 sigma (k = 2 x_mean
  // 1e-5) is the curvature cause: chi2 = (1e-5)^2 / (1e-10 + (1e-4 / 20)^2).
  OneSignedSlopeInputs off = in;
  off.k = 2.0 * -g * 1e-5;
  const OneSignedSlope c = weighOneSignedSlope(off);
  EXPECT_EQ(c.best, SlopeCause::kCurvature);
  EXPECT_NEAR(c.chi2_curvature, 1e-10 / (1e-10 + 2.5e-11), 1e-9);
  EXPECT_NEAR(c.k2, c2 + 1e-5 * 1e-10 / (1e-10 + 2.5e-11), 1e-12) << "lab and field combined";
  EXPECT_GT(c.margin, 6.0);
  // With the quadratic all a folded asymmetry (d = g c2) the field's slope is d, and the
  // asymmetry fits.
  OneSignedSlopeInputs fold = in;
  fold.k = g * c2;  // z1 = k + 2 c2 x_mean = g c2 - 2 g c2 = -g c2 = -d: d = g c2
  const OneSignedSlope f = weighOneSignedSlope(fold);
  EXPECT_EQ(f.best, SlopeCause::kAsymmetry);
  EXPECT_NEAR(f.d, g * c2, 1e-12);
  EXPECT_NEAR(f.k2_beside_d, 0.0, 1e-12);
}

TEST(GainOrCurvature, BadInputThrows) {
  EXPECT_THROW(weighOneSignedSlope(lineKept(1e-3, 0.0, -10.0, 0.0, 1e-5)), std::invalid_argument);
  EXPECT_THROW(weighOneSignedSlope(lineKept(1e-3, 1e-4, 0.0, 0.0, 1e-5)), std::invalid_argument);
  EXPECT_THROW(weighOneSignedSlope(lineKept(1e-3, 1e-4, -10.0, NAN, 1e-5)), std::invalid_argument);
  EXPECT_TRUE(oneSignedInput(-9.8, 0.3));
  EXPECT_FALSE(oneSignedInput(0.2, 1.0));
}

}  // namespace
}  // namespace graftnav
