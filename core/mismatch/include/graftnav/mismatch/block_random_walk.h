#pragma once
// A bias random walk seen through block means, and its intensity estimated by restricted maximum
// likelihood (REML) with slow regressors as fixed effects: the noise a slow term (a temperature
// warm-up) must be tested against (term_selection.h, step 3).
//
// Two bias realizations differ in the residual: the field's, and the lab's, which SG#2 replays
// from the lab's static record, tiled forward and backward in time (grafting.h). Their power sits
// on the longest time scales, where a warm-up lives. The block-mean variance (one number per
// channel) treats the blocks as independent and understated the wander's projection onto a
// smooth regressor about 8 x (docs/mismatch.md, Gaps). Here the block means y_b, b = 0..B-1,
// are modelled as
//   y = X beta + n,  cov(n) = v0 I + q K,
// v0 the white block-mean variance (known from the fine scales) and q >= 0 the intensity per
// block of each realization. K sums the realizations' block-mean covariances for a unit
// intensity, in block units: the field's Brownian motion (K_ab = min(a, b) + 1/2 for a != b,
// K_aa = a + 1/3) and, for SG#2, the replay, a Brownian motion over the static record read along
// the tiling's fold, which returns on itself every record length. REML keeps the fixed effects
// (the mean and the slow regressors' block means) from being counted as wander and accounts for
// the degrees of freedom they take.

#include <Eigen/Core>
#include <vector>

namespace graftnav {

// The field realization's K for `blocks` block means.
Eigen::MatrixXd blockRandomWalkCovariance(int blocks);

// Where a replayed record sits in the tiling: block b covers tiling times
// [start_s + b block_s, start_s + (b + 1) block_s); the record (length period_s) runs forward on
// even tiles and backward on odd ones (BasicErrorSignal::cumulative).
struct ReplayTiling {
  double period_s = 0.0;  // 0: no replay
  double start_s = 0.0;
  double block_s = 0.0;
};

// The replay's block-mean covariance for a unit intensity, in block units: the mean over both
// blocks of min(fold(s), fold(t)) / block_s, the fold taken at `nodes` midpoints per block.
Eigen::MatrixXd replayedRandomWalkCovariance(int blocks, const ReplayTiling& tiling,
                                             int nodes = 24);

// REML estimate of q (per block, in the units of y squared) for series y[c] with fixed effects
// X[c] (blocks x p, the constant included by the caller) sharing one intensity (the three axes of
// one sensor triad, whose wander has one specification; the REML deviances add), white variance
// white_var and unit covariance K. Maximized on a log grid of q / white_var from 1e-4 (and q = 0),
// about 1.14 per step, to 1e5 and beyond while the fit still improves. Returns 0 when all together leave fewer than 3 residual degrees
// of freedom, or an X is rank deficient or leaves none.
double remlBlockRandomWalk(const std::vector<Eigen::VectorXd>& y,
                           const std::vector<Eigen::MatrixXd>& X, double white_var,
                           const Eigen::MatrixXd& K);

}  // namespace graftnav
