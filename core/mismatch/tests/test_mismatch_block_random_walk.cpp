// The block random walk and its REML intensity (mismatch/block_random_walk.h): the noise a slow
// term of the mismatch finder is tested against.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "graftnav/imu/gauss_markov.h"
#include "graftnav/mismatch/block_random_walk.h"

namespace graftnav {
namespace {

constexpr int kBinsPerBlock = 200;

// Block means of white noise (unit variance per bin) plus a Brownian motion whose intensity per
// block is q (variance added per block length), started at 0.
Eigen::VectorXd blockMeansOfWalk(int blocks, double q, StandardNormalSampler* rng) {
  Eigen::VectorXd y(blocks);
  const double step_sd = std::sqrt(q / kBinsPerBlock);
  double walk = 0.0;
  for (int b = 0; b < blocks; ++b) {
    double acc = 0.0;
    for (int i = 0; i < kBinsPerBlock; ++i) {
      walk += step_sd * rng->next();
      acc += walk + rng->next();
    }
    y(b) = acc / kBinsPerBlock;
  }
  return y;
}

// One series against the field walk's covariance.
double reml(const Eigen::VectorXd& y, const Eigen::MatrixXd& X, double white_var) {
  return remlBlockRandomWalk({y}, {X}, white_var,
                             blockRandomWalkCovariance(static_cast<int>(y.size())));
}

Eigen::VectorXd warmUp(int blocks) {
  Eigen::VectorXd u(blocks);
  for (int b = 0; b < blocks; ++b) u(b) = 1.0 - std::exp(-(b + 0.5) / 4.0);
  return u;
}

// K is the covariance of block means of a unit Brownian motion: the sample covariance of
// simulated block means matches it within Monte-Carlo error.
TEST(BlockRandomWalk, CovarianceMatchesSimulatedBlockMeans) {
  const int blocks = 6, reps = 4000;
  StandardNormalSampler rng(7);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(blocks, blocks);
  const double step_sd = std::sqrt(1.0 / kBinsPerBlock);
  for (int r = 0; r < reps; ++r) {
    Eigen::VectorXd y(blocks);
    double walk = 0.0;
    for (int b = 0; b < blocks; ++b) {
      double acc = 0.0;
      for (int i = 0; i < kBinsPerBlock; ++i) {
        walk += step_sd * rng.next();
        acc += walk;
      }
      y(b) = acc / kBinsPerBlock;
    }
    S += y * y.transpose() / reps;
  }
  const Eigen::MatrixXd K = blockRandomWalkCovariance(blocks);
  for (int a = 0; a < blocks; ++a)
    for (int b = 0; b < blocks; ++b)
      EXPECT_NEAR(S(a, b), K(a, b), 0.06 * std::sqrt(K(a, a) * K(b, b)) + 0.02) << a << "," << b;
  EXPECT_NEAR(K(0, 0), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(K(1, 3), 1.5, 1e-12);
}

// The replay of a finite record tiled forward and backward (as SG#2 replays the lab's static
// record): the sample covariance of the replayed walk's block means matches the fold's K, and
// past one record length the replay returns on itself, so its variance stays bounded where the
// field's own walk keeps growing.
TEST(BlockRandomWalk, ReplayedRecordCovarianceFollowsTheFold) {
  ReplayTiling tiling;
  tiling.period_s = 600.0;
  tiling.block_s = 60.0;
  tiling.start_s = 130.0;
  const int blocks = 16, reps = 3000, per_s = 4;  // the record sampled at 4 Hz
  const int samples = static_cast<int>(tiling.period_s) * per_s;
  StandardNormalSampler rng(21);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(blocks, blocks);
  const double step_sd = std::sqrt(1.0 / (tiling.block_s * per_s));  // unit intensity per block
  std::vector<double> walk(samples + 1);
  for (int r = 0; r < reps; ++r) {
    walk[0] = 0.0;
    for (int i = 1; i <= samples; ++i) walk[i] = walk[i - 1] + step_sd * rng.next();
    Eigen::VectorXd y = Eigen::VectorXd::Zero(blocks);
    const int per_block = static_cast<int>(tiling.block_s) * per_s;
    for (int b = 0; b < blocks; ++b) {
      for (int i = 0; i < per_block; ++i) {
        const double u = tiling.start_s + b * tiling.block_s + (i + 0.5) / per_s;
        const double tile = std::floor(u / tiling.period_s);
        const double tau = u - tile * tiling.period_s;
        const double p = static_cast<long>(tile) % 2 == 0 ? tau : tiling.period_s - tau;
        y(b) += walk[static_cast<int>(std::lround(p * per_s))];
      }
      y(b) /= per_block;
    }
    S += y * y.transpose() / reps;
  }
  const Eigen::MatrixXd K = replayedRandomWalkCovariance(blocks, tiling);
  for (int a = 0; a < blocks; ++a)
    for (int b = 0; b < blocks; ++b)
      EXPECT_NEAR(S(a, b), K(a, b), 0.07 * std::sqrt(K(a, a) * K(b, b)) + 0.03) << a << "," << b;
  EXPECT_LT(K.diagonal().maxCoeff(), 10.0 + 1e-9);  // never beyond the record's end (10 blocks)
  EXPECT_GT(blockRandomWalkCovariance(blocks)(blocks - 1, blocks - 1), 15.0);
  EXPECT_EQ(replayedRandomWalkCovariance(blocks, ReplayTiling{}).norm(), 0.0);
}

// The intensity is recovered (median over draws within 25 %, as 15 block means allow), and a
// warm-up among the fixed effects leaves the estimate exactly unchanged whatever its size (REML
// sees only contrasts orthogonal to the fixed effects), while left out it is taken for wander.
TEST(BlockRandomWalk, RemlRecoversTheIntensityAndIgnoresFixedEffects) {
  const int blocks = 15, reps = 300;
  const double white_var = 1.0 / kBinsPerBlock;
  for (double q_true : {0.05 * white_var, 2.0 * white_var, 40.0 * white_var, 1e6 * white_var}) {
    std::vector<double> est;
    StandardNormalSampler rng(11);
    for (int r = 0; r < reps; ++r) {
      const Eigen::VectorXd y = blockMeansOfWalk(blocks, q_true, &rng);
      Eigen::MatrixXd X(blocks, 2);
      X.col(0).setOnes();
      X.col(1) = warmUp(blocks);
      const double q = reml(y, X, white_var);
      est.push_back(q);
      if (r < 20) {
        const Eigen::VectorXd with_warm_up =
            y + 50.0 * std::sqrt(q_true + white_var) * warmUp(blocks);
        EXPECT_DOUBLE_EQ(reml(with_warm_up, X, white_var), q);
        EXPECT_GT(reml(with_warm_up, X.leftCols(1), white_var), 4.0 * q + white_var);
      }
    }
    std::nth_element(est.begin(), est.begin() + reps / 2, est.end());
    const double median = est[reps / 2];
    if (q_true >= white_var)
      EXPECT_NEAR(median / q_true, 1.0, 0.25) << "q_true / white " << q_true / white_var;
    else
      EXPECT_LT(median, 0.5 * white_var) << "q_true / white " << q_true / white_var;
  }
}

TEST(BlockRandomWalk, TooFewDegreesOfFreedomGiveZero) {
  StandardNormalSampler rng(3);
  const Eigen::VectorXd y = blockMeansOfWalk(5, 1.0, &rng);
  Eigen::MatrixXd X = Eigen::MatrixXd::Ones(5, 3);
  X.col(1) = Eigen::VectorXd::LinSpaced(5, 0, 1);
  X.col(2) = X.col(1).cwiseAbs2();
  EXPECT_EQ(reml(y, X, 1.0), 0.0);              // 5 - 3 < 3
  EXPECT_EQ(reml(y, X.leftCols(1), 0.0), 0.0);  // no white variance
  Eigen::MatrixXd Xd(5, 2);
  Xd << Eigen::VectorXd::Ones(5), Eigen::VectorXd::Ones(5);
  EXPECT_EQ(reml(y, Xd, 1.0), 0.0);  // rank deficient
  // Three axes sharing one intensity: 3 x (5 - 3) = 6 degrees of freedom are enough.
  const Eigen::MatrixXd K = blockRandomWalkCovariance(5);
  EXPECT_GE(remlBlockRandomWalk({y, y, y}, {X, X, X}, 1e-3, K), 0.0);
  EXPECT_GT(remlBlockRandomWalk({y, 2.0 * y, -y}, {X, X, X}, 1e-6, K), 0.0);
}

}  // namespace
}  // namespace graftnav
