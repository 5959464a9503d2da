#pragma once
// Internal to the mismatch module's term selection (term_selection.h): the slow noise.
// The AR(1) model leaves out noise with long correlation (a bias random process whose field and
// lab realizations differ). Per channel, the whitened residual of the full model without the
// slow candidates (bias wander, temperature, Earth/gravity) is split into Haar levels and its
// variance per level is smoothed by the law c_j = 1 + a 2^j + b 4^j (scale_noise.h). The fit
// is then generalized least squares: every channel's whitened rows (residual and regressors)
// are Haar transformed and level j is weighted by 1 / c_j. A slow regressor (a warm-up, the
// drive's acceleration pattern) meets the noise of its own time scales, and a term acting on
// several channels keeps the information of its quiet channels (a misalignment's gyro rows)
// while its noisy ones (the accelerometers' bias wander) count for less.
// For a fast term (not slow itself), the slow terms already in the model it is tested against
// (`base`: selected, so they passed this test themselves) stay in that residual: their signal
// is established physics, not noise. Without that, a temperature warm-up in the gyro residual
// raised the slow noise 10-fold and cost a g-sensitivity (whose specific-force regressor has
// slow content) its detection. A slow term is always measured against the residual without any
// slow term (claimed slow physics and bias wander are the very ambiguity it must overcome).
#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <vector>

#include "graftnav/mismatch/scale_noise.h"
#include "selection_models.h"
#include "selection_noise_model.h"

namespace graftnav::selection_detail {

// The normal equations a term is fitted and tested on, with the factors of its noise.
struct SlowNoise {
  Eigen::Matrix<double, 6, 1> slow_inflation = Eigen::Matrix<double, 6, 1>::Ones();
  // Normal equations of the GLS (all columns), as GramSet's *_all.
  Eigen::MatrixXd G;
  Eigen::VectorXd b;
  double yy = 0.0;
  // Per term: the factor its evidence's data term is divided by and its covariance multiplied
  // by on top of c: 1 under GLS, the block-mean factor for a slow term (white fit).
  std::vector<double> term_inflation;
  // The same normal equations per CV fold (step 3), each fold's rows Haar transformed on their
  // own and weighted by the same 1 / c_j, so cross-validation measures prediction errors in the
  // metric the terms are fitted and tested in.
  std::vector<Eigen::MatrixXd> G_fold;
  std::vector<Eigen::VectorXd> b_fold;
  std::vector<double> yy_fold;
  // The per-channel law of the GLS (estimateSlowNoise only), for the sandwich covariance.
  std::array<ScaleNoiseModel, kMismatchChannels> law;
  bool has_law = false;
};

// Per channel, the level-j parts of the normal equations of the whitened rows (as accumulate
// builds them) of the columns acting on it: [X y]' [X y] of the Haar level-j coefficients.
struct ChannelLevels {
  std::vector<int> idx;               // global column indices
  std::vector<Eigen::MatrixXd> gram;  // per Haar level, (m + 1) x (m + 1), y last
  // Per CV fold (the folds of accumulate), its rows transformed on their own, per level.
  std::vector<std::vector<Eigen::MatrixXd>> fold_gram;
};

class SlowNoiseEstimator {
 public:
  // `noise` and `models` must outlive the estimator.
  SlowNoiseEstimator(const SelectionNoiseModel& noise, const TermModels& models);

  // The GLS noise of a fast term tested against the model `base` (its slow terms stay in the
  // residual), or with `for_slow_term` the block-mean noise every slow term is tested against.
  // Cached: the returned addresses are stable for the estimator's lifetime.
  const SlowNoise& slowNoise(const std::vector<int>& base, bool for_slow_term = false) const;
  // The slow noise term t is tested against, with the model `base` (which does not hold t).
  const SlowNoise& slowNoiseFor(int t, const std::vector<int>& base) const;
  // The meat X'W Sigma W X of the sandwich covariance over the free columns S.
  Eigen::MatrixXd randomWalkMeat(const SlowNoise& sn, const std::vector<int>& S) const;

 private:
  const std::array<ChannelLevels, kMismatchChannels>& levelGrams() const;
  Eigen::MatrixXd slowResidual(const std::vector<int>& slow_in_model) const;
  SlowNoise whiteNoise() const;
  int slowBlocks() const;
  SlowNoise blockMeanNoise() const;
  SlowNoise estimateSlowNoise(const std::vector<int>& slow_in_model) const;

  const std::vector<CandidateTerm>& terms_;
  const SelectionOptions& opt_;
  const SelectionNoiseModel& noise_;
  const TermModels& models_;
  mutable std::map<std::vector<int>, SlowNoise> slow_cache_;  // SlowNoise addresses are stable
  mutable std::unique_ptr<std::array<ChannelLevels, kMismatchChannels>> level_grams_;
};

}  // namespace graftnav::selection_detail
