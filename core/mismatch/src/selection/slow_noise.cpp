#include "slow_noise.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>

#include "graftnav/mismatch/block_random_walk.h"

namespace graftnav::selection_detail {

SlowNoiseEstimator::SlowNoiseEstimator(const SelectionNoiseModel& noise, const TermModels& models)
    : terms_(noise.terms()), opt_(noise.options()), noise_(noise), models_(models) {}

// `for_slow_term`: the noise a slow term is measured against (blockMeanNoise).
const SlowNoise& SlowNoiseEstimator::slowNoise(const std::vector<int>& base,
                                               bool for_slow_term) const {
  std::vector<int> slow_in_base;
  for (int t : base)
    if (models_.isSlow(t)) slow_in_base.push_back(t);
  if (for_slow_term) slow_in_base.push_back(-1);  // its own cache entry
  auto it = slow_cache_.find(slow_in_base);
  if (it == slow_cache_.end()) {
    if (for_slow_term) slow_in_base.pop_back();
    SlowNoise sn = for_slow_term ? blockMeanNoise() : estimateSlowNoise(slow_in_base);
    if (for_slow_term) slow_in_base.push_back(-1);
    it = slow_cache_.emplace(slow_in_base, std::move(sn)).first;
  }
  return it->second;
}

// The slow noise term t is tested against, with the model `base` (which does not hold t).
const SlowNoise& SlowNoiseEstimator::slowNoiseFor(int t, const std::vector<int>& base) const {
  return models_.isSlow(t) ? slowNoise({}, true) : slowNoise(base);
}

const std::array<ChannelLevels, kMismatchChannels>& SlowNoiseEstimator::levelGrams() const {
  if (!level_grams_) {
    level_grams_ = std::make_unique<std::array<ChannelLevels, kMismatchChannels>>();
    const int len = noise_.rowEnd() - noise_.rowBegin();
    for (int c = 0; c < kMismatchChannels; ++c) {
      ChannelLevels& cl = (*level_grams_)[c];
      ChannelColumns cols = channelColumns(terms_, noise_.map(), c);
      cl.idx = std::move(cols.idx);
      const Eigen::VectorXd rc = noise_.residual().col(c);
      // The whitened columns and residual (y last) a block of rows at a time, into the Haar
      // levels of the whole record and of the fold the block lies in.
      const Eigen::Index width = static_cast<Eigen::Index>(cols.src.size()) + 1;
      HaarLevelGramAccumulator whole(len, width);
      const int folds = static_cast<int>(noise_.gram().G.size());
      cl.fold_gram.resize(folds);
      for (int f = 0; f < folds; ++f) {
        const int a = foldStart(len, f, folds), b = foldStart(len, f + 1, folds);
        HaarLevelGramAccumulator fold(b - a, width);
        for (int i = a; i < b; i += kGramBlockRows) {
          const Eigen::MatrixXd Xy =
              whitenedBlock(cols, &rc, noise_.rowBegin(), i, std::min(b, i + kGramBlockRows),
                            noise_.rho()(c), 1.0 / noise_.sigma()(c));
          whole.add(Xy);
          fold.add(Xy);
        }
        cl.fold_gram[f] = fold.grams();
      }
      cl.gram = whole.grams();
    }
  }
  return *level_grams_;
}

// The residual of the fast model plus the slow terms `slow_in_model` (whitened, mean removed).
Eigen::MatrixXd SlowNoiseEstimator::slowResidual(const std::vector<int>& slow_in_model) const {
  std::vector<int> fast;
  for (int t : noise_.fullModel())
    if (!models_.isSlow(t)) fast.push_back(t);
  for (int t : slow_in_model) fast = models_.withTerm(fast, t);
  std::vector<int> S, F;
  modelColumns(fast, terms_, noise_.map(), &S, &F);
  const ModelFit fit =
      solve(noise_.gram().G_all, noise_.gram().b_all, noise_.gram().yy_all, S, F, false);
  const Eigen::MatrixXd e = residualOf(noise_.residual(), terms_, noise_.map(), fast, fit,
                                       noise_.rowBegin(), noise_.rowEnd());
  Eigen::MatrixXd w(e.rows(), e.cols());
  for (int c = 0; c < kMismatchChannels; ++c) w.col(c) = noise_.whitened(e.col(c), c, 0);
  return w;
}

// The AR(1)-whitened normal equations as they are (no slow-noise weighting, factors 1).
SlowNoise SlowNoiseEstimator::whiteNoise() const {
  SlowNoise out;
  out.G = noise_.gram().G_all;
  out.b = noise_.gram().b_all;
  out.yy = noise_.gram().yy_all;
  out.G_fold = noise_.gram().G;
  out.b_fold = noise_.gram().b;
  out.yy_fold = noise_.gram().yy;
  out.term_inflation.assign(terms_.size(), 1.0);
  return out;
}

// Whole slow-noise blocks in the fitted rows (0 when the check is off).
int SlowNoiseEstimator::slowBlocks() const {
  const int m = opt_.slow_block_bins;
  return m > 1 ? (noise_.rowEnd() - noise_.rowBegin()) / m : 0;
}

// A slow term (temperature, bias wander, Earth/gravity) against the slow noise: a warm-up and a
// bias wander share the coarse time scales, where the record holds only a few coefficients, so
// neither a law fitted below them nor GLS weights can tell them apart (both left the gyro
// temperature sigmas 3-5x small on the concealed cases). The slow term is fitted by white least
// squares and its evidence and covariance carry one factor, 1 + sum_c s_c (c_slow_c - 1): per
// channel c_slow = block length x variance of the block means of the residual without any slow
// term (1 for white noise; it holds whatever slow signal is there, the conservative side), s_c
// the share of the term's whitened regressor energy in block means on channel c. Or, when
// larger, the factor of a random walk of the block means whose intensity REML estimates with
// the term's own regressors as fixed effects (block_random_walk.h): the block factor treats
// the blocks as independent, and a random walk's projection onto a warm-up is ~8 x larger.
SlowNoise SlowNoiseEstimator::blockMeanNoise() const {
  SlowNoise out = whiteNoise();
  const int m = opt_.slow_block_bins;
  const int blocks = slowBlocks();
  if (blocks < 4) return out;
  const auto blockMeans = [&](const Eigen::VectorXd& w) {
    Eigen::VectorXd out_b(blocks);
    for (int b = 0; b < blocks; ++b) out_b(b) = w.segment(b * m, m).mean();
    return out_b;
  };
  // The energy of w in its block means (m per block mean squared).
  const auto blockEnergy = [&](const Eigen::VectorXd& means) { return m * means.squaredNorm(); };
  const Eigen::MatrixXd e = slowResidual({});
  for (int c = 0; c < kMismatchChannels; ++c)
    out.slow_inflation(c) =
        std::max(1.0, blockEnergy(blockMeans(e.col(c))) / blocks / noise_.inflation());
  // The two realizations' unit covariance: the field's walk, plus the lab's replayed one when
  // the simulation is SG#2 (block b starts rb_ + b m bins into the grid).
  Eigen::MatrixXd K = blockRandomWalkCovariance(blocks);
  if (opt_.replay_period_s > 0.0 && opt_.bin_s > 0.0) {
    ReplayTiling tiling;
    tiling.period_s = opt_.replay_period_s;
    tiling.block_s = m * opt_.bin_s;
    tiling.start_s = opt_.replay_start_s + noise_.rowBegin() * opt_.bin_s;
    K += replayedRandomWalkCovariance(blocks, tiling);
  }
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    double num = 0.0, num_walk = 0.0, total = 0.0;
    std::optional<Eigen::MatrixXd> own_residual;
    // Per sensor triad (gyro channels 0-2, accel 3-5): the term's whitened columns on each
    // channel as block means, and that channel's residual block means.
    for (const Sensor sensor : kSensors) {
      std::vector<std::vector<Eigen::VectorXd>> means(3);
      for (int k = 0; k < 3; ++k) {
        const int c = firstChannel(sensor) + k;
        for (const RegressorColumn& col : terms_[t].columns) {
          if (!col.actsOn(c)) continue;
          const Eigen::VectorXd w = noise_.whitened(col.dense(c), c, noise_.rowBegin());
          const double energy = w.squaredNorm();
          means[k].push_back(blockMeans(w));
          num += std::min(blockEnergy(means[k].back()), energy) * (out.slow_inflation(c) - 1.0);
          total += energy;
        }
      }
      if (!models_.isSlow(static_cast<int>(t))) continue;
      // One random walk per triad (its axes share one wander specification), its intensity
      // by REML with this term's regressors as fixed effects on each channel, in the residual
      // of the fast model fitted together with this term (fitted without it, the fast terms
      // take up part of a real warm-up and leave a shape REML would call wander).
      std::vector<Eigen::VectorXd> ys;
      std::vector<Eigen::MatrixXd> Xs;
      for (int k = 0; k < 3; ++k) {
        if (means[k].empty()) continue;
        if (!own_residual) own_residual = slowResidual({static_cast<int>(t)});
        Eigen::MatrixXd X(blocks, static_cast<int>(means[k].size()) + 1);
        X.col(0).setOnes();
        for (std::size_t j = 0; j < means[k].size(); ++j)
          X.col(static_cast<int>(j) + 1) = means[k][j];
        ys.push_back(blockMeans(own_residual->col(firstChannel(sensor) + k)));
        Xs.push_back(std::move(X));
      }
      if (ys.empty()) continue;
      const double q = remlBlockRandomWalk(ys, Xs, noise_.inflation() / m, K);
      // var(u'e) - var(u'e | white) = m^2 q u_b' K u_b per column (u_b its block means).
      for (int k = 0; k < 3; ++k)
        for (const Eigen::VectorXd& u : means[k]) {
          const Eigen::VectorXd d = u.array() - u.mean();
          num_walk += static_cast<double>(m) * m * q * d.dot(K * d);
        }
    }
    if (!(total > 0.0)) continue;
    // The block-mean factor holds whatever slow signal is in the residual but treats the
    // blocks as independent; the random walk's factor follows the wander onto the regressor's
    // own time scales. The larger one is used.
    const double f_block = 1.0 + num / total, f_walk = 1.0 + num_walk / total;
    out.term_inflation[t] = std::max(f_block, f_walk);
  }
  return out;
}

SlowNoise SlowNoiseEstimator::estimateSlowNoise(const std::vector<int>& slow_in_model) const {
  SlowNoise out = whiteNoise();
  const int m = opt_.slow_block_bins;
  const int blocks = slowBlocks();
  if (blocks < 4) return out;
  const Eigen::MatrixXd e = slowResidual(slow_in_model);
  // Per channel, the residual's noise per Haar scale, the law fitted on the levels up to twice
  // the block length (coarser ones hold slow physics, a warm-up, that is not noise to a fast
  // term; the law extrapolates the wander there); reported at the block length.
  const int report_level = std::max(1, static_cast<int>(std::lround(std::log2(m))));
  const auto& lg = levelGrams();
  const int P = noise_.map().total;
  out.G = Eigen::MatrixXd::Zero(P, P);
  out.b = Eigen::VectorXd::Zero(P);
  out.yy = 0.0;
  const int folds = static_cast<int>(noise_.gram().G.size());
  out.G_fold.assign(folds, Eigen::MatrixXd::Zero(P, P));
  out.b_fold.assign(folds, Eigen::VectorXd::Zero(P));
  out.yy_fold.assign(folds, 0.0);
  // Adds the level grams of one channel, level j weighted by 1 / c_j.
  const auto addLevels = [](const ChannelLevels& cl, const std::vector<Eigen::MatrixXd>& grams,
                            const ScaleNoiseModel& model, Eigen::MatrixXd* G, Eigen::VectorXd* b,
                            double* yy) {
    const int k = static_cast<int>(cl.idx.size());
    for (std::size_t j = 0; j < grams.size(); ++j) {
      const double w = 1.0 / model.at(static_cast<int>(j) + 1);
      const Eigen::MatrixXd& g = grams[j];
      for (int a = 0; a < k; ++a) {
        (*b)(cl.idx[a]) += w * g(a, k);
        for (int bb = 0; bb < k; ++bb) (*G)(cl.idx[a], cl.idx[bb]) += w * g(a, bb);
      }
      *yy += w * g(k, k);
    }
  };
  for (int c = 0; c < kMismatchChannels; ++c) {
    const ScaleNoiseModel model =
        fitScaleNoise(haarEnergies(e.col(c)), noise_.inflation(), report_level + 1);
    out.slow_inflation(c) = model.at(report_level);
    out.law[c] = model;
    const ChannelLevels& cl = lg[c];
    addLevels(cl, cl.gram, model, &out.G, &out.b, &out.yy);
    for (int f = 0; f < folds; ++f)
      addLevels(cl, cl.fold_gram[f], model, &out.G_fold[f], &out.b_fold[f], &out.yy_fold[f]);
  }
  out.has_law = true;
  return out;
}

// The meat X'W Sigma W X of the sandwich covariance over the free columns S (options'
// random_walk_sandwich), in the whitened units of the fit (white part 1, the law's c_j relative
// to it). Per channel: the columns' Haar levels weighted by 1 / c_j (W X), mapped back to time
// (V); then V'V (white) + 12 b (L'V)'(L'V) (the random walk: Var(v'x) = q sum_s (sum_{t>=s}
// v_t)^2, L' the reverse cumulative sum) + sum_j a 2^j (W X)_j' (W X)_j (the 2^j part taken
// level-diagonal).
Eigen::MatrixXd SlowNoiseEstimator::randomWalkMeat(const SlowNoise& sn,
                                                   const std::vector<int>& S) const {
  const int p = static_cast<int>(S.size());
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(p, p);
  const int len = noise_.rowEnd() - noise_.rowBegin();
  for (int c = 0; c < kMismatchChannels; ++c) {
    const ChannelColumns all = channelColumns(terms_, noise_.map(), c);
    std::vector<int> pos;  // the free columns on channel c: their places in S
    ChannelColumns free;
    free.channel = c;
    for (std::size_t k = 0; k < all.idx.size(); ++k) {
      const auto it = std::find(S.begin(), S.end(), all.idx[k]);
      if (it == S.end()) continue;
      pos.push_back(static_cast<int>(it - S.begin()));
      free.idx.push_back(all.idx[k]);
      free.src.push_back(all.src[k]);
    }
    const int m = static_cast<int>(free.src.size());
    if (m == 0) continue;
    std::vector<Eigen::MatrixXd> levels = haarCoefficients(whitenedColumns(
        free, nullptr, noise_.rowBegin(), len, noise_.rho()(c), 1.0 / noise_.sigma()(c)));
    const ScaleNoiseModel& law = sn.law[c];
    Eigen::MatrixXd Bc = Eigen::MatrixXd::Zero(m, m);
    for (std::size_t j = 0; j < levels.size(); ++j) {
      const int level = static_cast<int>(j) + 1;
      levels[j] /= law.at(level);
      Bc += law.a * std::ldexp(1.0, level) * levels[j].transpose() * levels[j];
    }
    const Eigen::MatrixXd V = haarSynthesis(levels, len);
    Eigen::MatrixXd tail = V;  // reverse cumulative sums
    for (int i = len - 2; i >= 0; --i) tail.row(i) += tail.row(i + 1);
    Bc += V.transpose() * V + 12.0 * law.b * tail.transpose() * tail;
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) B(pos[a], pos[b]) += Bc(a, b);
  }
  return B;
}

}  // namespace graftnav::selection_detail
