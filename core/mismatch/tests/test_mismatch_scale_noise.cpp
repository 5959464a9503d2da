// Noise per Haar scale (mismatch/scale_noise.h) and the generalized least squares the term
// selection builds on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "graftnav/mismatch/scale_noise.h"
#include "graftnav/imu/gauss_markov.h"

namespace graftnav {
namespace {

// The levels partition the Gram matrix exactly, odd lengths included: GLS with unit weights is
// ordinary least squares.
TEST(ScaleNoise, HaarLevelsPartitionTheGramMatrix) {
  StandardNormalSampler rng(1);
  for (int n : {4, 5, 17, 1000, 1023}) {
    Eigen::MatrixXd X(n, 3);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 3; ++j) X(i, j) = rng.next() + (j == 2 ? 0.01 * i : 0.0);
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(3, 3);
    for (const Eigen::MatrixXd& D : haarCoefficients(X)) sum += D.transpose() * D;
    EXPECT_LT((sum - X.transpose() * X).norm(), 1e-9 * (X.transpose() * X).norm()) << "n " << n;
  }
}

// The per-level normal equations made one level at a time are those of the held levels, to the
// last bit, for every length (no transform below 4 rows, odd rows left at several levels).
TEST(ScaleNoise, HaarLevelGramsEqualTheGramsOfTheLevels) {
  StandardNormalSampler rng(3);
  for (int n : {1, 3, 4, 5, 7, 17, 1000, 1023}) {
    Eigen::MatrixXd X(n, 3);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 3; ++j) X(i, j) = rng.next() + (j == 2 ? 0.01 * i : 0.0);
    const std::vector<Eigen::MatrixXd> levels = haarCoefficients(X);
    const std::vector<Eigen::MatrixXd> grams = haarLevelGrams(X);
    ASSERT_EQ(grams.size(), levels.size()) << "n " << n;
    for (std::size_t j = 0; j < levels.size(); ++j) {
      const Eigen::MatrixXd expected = levels[j].transpose() * levels[j];
      EXPECT_TRUE(grams[j] == expected) << "n " << n << " level " << j;
    }
  }
}

// Rows handed over in blocks of any size give the per-level normal equations of the held
// matrix, to rounding (the order of summation differs), with every kind of level: none below 4
// rows, odd rows left at several levels, more detail rows than one buffer.
TEST(ScaleNoise, HaarLevelGramsAccumulatedByBlocksEqualTheHeldOnes) {
  StandardNormalSampler rng(5);
  for (int n : {1, 3, 4, 5, 7, 17, 1000, 1023, 5001}) {
    Eigen::MatrixXd X(n, 4);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 4; ++j) X(i, j) = rng.next() + (j == 3 ? 0.01 * i : 0.0);
    const std::vector<Eigen::MatrixXd> held = haarLevelGrams(X);
    for (int block : {1, 3, 64, 4096}) {
      HaarLevelGramAccumulator acc(n, 4);
      for (int i = 0; i < n; i += block) acc.add(X.middleRows(i, std::min(block, n - i)));
      const std::vector<Eigen::MatrixXd> grams = acc.grams();
      ASSERT_EQ(grams.size(), held.size()) << "n " << n;
      for (std::size_t j = 0; j < held.size(); ++j)
        EXPECT_LT((grams[j] - held[j]).norm(), 1e-12 * held[j].norm())
            << "n " << n << " level " << j << " blocks of " << block;
    }
  }
  HaarLevelGramAccumulator short_of_rows(10, 2);
  short_of_rows.add(Eigen::MatrixXd::Ones(9, 2));
  EXPECT_THROW(short_of_rows.grams(), std::logic_error);
  EXPECT_THROW(short_of_rows.add(Eigen::MatrixXd::Ones(2, 2)), std::invalid_argument);
}

// Synthesis inverts the transform, odd lengths and leftover rows included (1-3 rows: no
// transform), and a weighted level maps back to the time series it stands for.
TEST(ScaleNoise, HaarSynthesisInvertsTheCoefficients) {
  StandardNormalSampler rng(2);
  for (int n : {1, 3, 4, 5, 7, 17, 1000, 1023, 22581}) {
    Eigen::MatrixXd X(n, 2);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 2; ++j) X(i, j) = rng.next() + (j == 1 ? 0.01 * i : 0.0);
    const std::vector<Eigen::MatrixXd> levels = haarCoefficients(X);
    const Eigen::MatrixXd back = haarSynthesis(levels, n);
    ASSERT_EQ(back.rows(), n);
    EXPECT_LT((back - X).norm(), 1e-10 * X.norm()) << "n " << n;
    // Linear: scaling one level scales only that level's part of the series.
    if (levels.size() > 2) {
      std::vector<Eigen::MatrixXd> scaled = levels;
      scaled[1] *= 3.0;
      const std::vector<Eigen::MatrixXd> again = haarCoefficients(haarSynthesis(scaled, n));
      EXPECT_LT((again[1] - 3.0 * levels[1]).norm(), 1e-9 * levels[1].norm()) << "n " << n;
      EXPECT_LT((again[0] - levels[0]).norm(), 1e-9 * levels[0].norm()) << "n " << n;
    }
  }
  EXPECT_THROW(haarSynthesis(haarCoefficients(Eigen::MatrixXd::Ones(100, 1)), 50),
               std::invalid_argument);
}

// White noise plus a random walk: the law fitted on the fine and middle levels predicts the
// coarse levels' variance (averaged over realizations) within a factor 1.6; white noise alone
// gives c_j ~ 1 on the fitted levels and a bounded, conservative extrapolation beyond them.
TEST(ScaleNoise, LawFittedBelowTheCoarseLevelsPredictsThem) {
  const int n = 1 << 14;
  const int reps = 60;
  const int fit_levels = 10;
  for (double q : {0.0, 3e-3}) {  // random-walk step sd, in units of the white sd
    std::vector<double> mean_v;
    std::vector<double> mean_pred;
    for (int r = 0; r < reps; ++r) {
      StandardNormalSampler rng(100 + r);
      Eigen::VectorXd z(n);
      double walk = 0.0;
      for (int i = 0; i < n; ++i) {
        walk += q * rng.next();
        z(i) = rng.next() + walk;
      }
      z.array() -= z.mean();
      const HaarEnergies h = haarEnergies(z);
      const ScaleNoiseModel m = fitScaleNoise(h, 1.0, fit_levels);
      mean_v.resize(h.energy.size(), 0.0);
      mean_pred.resize(h.energy.size(), 0.0);
      for (std::size_t j = 0; j < h.energy.size(); ++j) {
        mean_v[j] += h.energy[j] / h.count[j] / reps;
        mean_pred[j] += m.at(static_cast<int>(j) + 1) / reps;
      }
    }
    for (std::size_t j = 0; j + 1 < mean_v.size(); ++j) {  // the last level holds 2-4 values
      if (q == 0.0 && j + 1 < static_cast<std::size_t>(fit_levels)) {
        EXPECT_NEAR(mean_pred[j], 1.0, 0.1) << "white, level " << j + 1;
      } else if (q == 0.0) {
        // From the last fitted level on, a chance rise at levels 8-10 is extrapolated as 4^j: on
        // white noise the law is conservative there (mean 1.15, 1.5, 2.6 at levels 10-12).
        EXPECT_LT(mean_pred[j], 4.0) << "white, level " << j + 1;
      } else if (j + 1 > static_cast<std::size_t>(fit_levels)) {
        EXPECT_LT(mean_pred[j], 1.6 * mean_v[j]) << "level " << j + 1;
        EXPECT_GT(mean_pred[j], mean_v[j] / 1.6) << "level " << j + 1;
      }
    }
  }
}

}  // namespace
}  // namespace graftnav
