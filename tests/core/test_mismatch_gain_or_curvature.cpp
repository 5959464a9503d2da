// weighGainAgainstCurvature (mismatch/gain_or_curvature.h): the margin and the combined k2
// against hand-computed values, its sign following the lab's degree-2 estimate, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/core/mismatch/gain_or_curvature.h"

namespace graftnav {
namespace {

TEST(GainOrCurvature, MarginAndCombinedCurvatureByHand) {
  // Field: k = 1.2e-3 +- 2e-4 at x_mean = -10 -> k2_field = -6e-5 +- 1e-5.
  // Lab: -5e-5 +- 2e-5. chi2_gain = 6.25; chi2_curvature = (1e-5)^2 / 5e-10 = 0.2.
  const GainOrCurvature w = weighGainAgainstCurvature({1.2e-3, 2e-4, -10.0, -5e-5, 2e-5});
  EXPECT_NEAR(w.k2_field, -6e-5, 1e-18);
  EXPECT_NEAR(w.k2_field_sigma, 1e-5, 1e-18);
  EXPECT_NEAR(w.margin, 6.25 - 0.2, 1e-9);
  // Inverse-variance mean: (-5e-5 / 4e-10 + -6e-5 / 1e-10) / (2.5e9 + 1e10) = -5.8e-5.
  EXPECT_NEAR(w.k2, -5.8e-5, 1e-15);
  EXPECT_NEAR(w.k2_sigma, std::sqrt(1.0 / 1.25e10), 1e-15);
}

TEST(GainOrCurvature, LabWithoutCurvatureSpeaksForAGain) {
  // The same field gain with a lab that sees no curvature (0 +- 1e-5): the gain changed.
  const GainOrCurvature gain = weighGainAgainstCurvature({1.2e-3, 2e-4, -10.0, 0.0, 1e-5});
  EXPECT_LT(gain.margin, -6.0);
  // A lab too coarse to tell (0 +- 2e-4): neither side has evidence.
  const GainOrCurvature coarse = weighGainAgainstCurvature({1.2e-3, 2e-4, -10.0, 0.0, 2e-4});
  EXPECT_GT(coarse.margin, -1.0);
  EXPECT_LE(coarse.margin, 0.0);
}

TEST(GainOrCurvature, BadInputThrows) {
  EXPECT_THROW(weighGainAgainstCurvature({1e-3, 0.0, -10.0, 0.0, 1e-5}), std::invalid_argument);
  EXPECT_THROW(weighGainAgainstCurvature({1e-3, 1e-4, 0.0, 0.0, 1e-5}), std::invalid_argument);
  EXPECT_THROW(weighGainAgainstCurvature({1e-3, 1e-4, -10.0, NAN, 1e-5}), std::invalid_argument);
  EXPECT_TRUE(oneSignedInput(-9.8, 0.3));
  EXPECT_FALSE(oneSignedInput(0.2, 1.0));
}

}  // namespace
}  // namespace graftnav
