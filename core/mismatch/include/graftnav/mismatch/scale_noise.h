#pragma once
// Noise whose power grows towards long periods (bias instability, random walk), measured per
// time scale with the orthonormal Haar transform: the model behind the mismatch finder's
// generalized least squares (term_selection.h, step 3).
//
// On Haar level j (scale 2^j samples) white, flicker and random-walk noise give close to
// uncorrelated coefficients with variance c_j relative to the white part: 1, ~2^j and ~4^j.
// Weighting level j by 1 / c_j whitens such noise, so least squares on the weighted
// coefficients is GLS. A slow regressor (a warm-up, a speed profile) puts its energy on the
// coarse levels, where a random walk's c_j is largest; one block length (a single split into
// 60-s block means and the rest) understated that by ~8x on warm-ups.
//
// The per-level variances v_j of a residual are noisy where few coefficients exist (the coarsest
// levels, exactly where slow regressors live), so they are smoothed by the power law of those
// noise types, c_j = 1 + a 2^j + b 4^j, a, b >= 0, fitted by weighted least squares (weights
// n_j / c_j^2, the inverse variance of v_j). The fine and middle levels, with many coefficients,
// set a and b; the coarse levels follow from the law rather than from their two or three
// coefficients (which would also hold any slow physics still in the residual).

#include <Eigen/Core>
#include <vector>

namespace graftnav {

// Energies of z on the Haar levels j = 1..J (index j - 1), J the deepest level that leaves at
// least 2 approximation coefficients, and of that final approximation (the slowest content). An
// odd sample left over at a level is dropped (at most one sample per level). count[j - 1] =
// detail coefficients on level j.
struct HaarEnergies {
  std::vector<double> energy;
  std::vector<int> count;
  double approximation = 0.0;
};
HaarEnergies haarEnergies(const Eigen::VectorXd& z);

// The Haar detail coefficients of the columns of X, level by level (index j - 1: an m_j x cols
// matrix); the last level also holds the final approximation's rows and the odd rows left over
// at each level (at most one per level), so sum_j D_j' D_j = X' X exactly. A noise that is white
// with variance c_j on level j is made white by dividing level j by sqrt(c_j): least squares
// on the scaled coefficients is generalized least squares (GLS) under that noise.
std::vector<Eigen::MatrixXd> haarCoefficients(const Eigen::MatrixXd& X);
// D'D of each level D of haarCoefficients(X), without holding the levels (normal equations per
// scale).
std::vector<Eigen::MatrixXd> haarLevelGrams(const Eigen::MatrixXd& X);

// haarLevelGrams of a matrix of `rows` rows handed over a block of rows at a time, holding one
// unpaired row per level and a buffer of detail rows, never the matrix: equal to
// haarLevelGrams(X) up to the order of summation.
class HaarLevelGramAccumulator {
 public:
  HaarLevelGramAccumulator(Eigen::Index rows, Eigen::Index cols);
  // The next rows of X, in order.
  void add(const Eigen::Ref<const Eigen::MatrixXd>& block);
  // After all `rows` rows: the grams per level (throws before).
  std::vector<Eigen::MatrixXd> grams();

 private:
  void feed(int level, const Eigen::Ref<const Eigen::RowVectorXd>& row);
  void addToGram(int level, const Eigen::Ref<const Eigen::RowVectorXd>& row);
  void flush(int level);
  Eigen::Index cols_;
  Eigen::Index added_ = 0;
  int levels_;                                // detail levels (0: X' X as one level)
  std::vector<Eigen::Index> size_, seen_;     // rows entering each level, and so far
  std::vector<Eigen::RowVectorXd> unpaired_;  // the even row waiting for its pair, per level
  std::vector<Eigen::MatrixXd> buffer_;       // rows not yet in the gram, per gram
  std::vector<int> buffered_;
  std::vector<Eigen::MatrixXd> gram_;
};

// The inverse of haarCoefficients for `rows` rows (the transform is orthonormal, so this is its
// transpose): X = haarSynthesis(haarCoefficients(X), X.rows()). Maps level-weighted coefficients
// back to time, e.g. a GLS-weighted regressor whose time-domain covariance is wanted.
Eigen::MatrixXd haarSynthesis(const std::vector<Eigen::MatrixXd>& levels, Eigen::Index rows);

// c_j = 1 + a 2^j + b 4^j for j = 1..levels (index j - 1), every c_j >= 1.
struct ScaleNoiseModel {
  double a = 0.0;
  double b = 0.0;
  int levels = 0;
  double at(int level) const;  // c_level; level clamped to [1, levels]
};

// Fits the model to the level variances v_j = energy_j / count_j of `residual` divided by
// `unit_variance` (white noise of that variance gives c_j = 1), on levels 1..max_fit_level only
// (0: all); the model still covers every level of `residual`. Slow physics still in the residual
// (a warm-up the model is testing for) lives on the coarse levels; fitting the law below them
// keeps it from being counted as noise against itself.
ScaleNoiseModel fitScaleNoise(const HaarEnergies& residual, double unit_variance = 1.0,
                              int max_fit_level = 0);

}  // namespace graftnav
