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

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/core.h>

#include "graftnav/mismatch/term_selection.h"

#include "graftnav/mismatch/block_random_walk.h"
#include "graftnav/mismatch/scale_noise.h"

namespace graftnav {

void SelectionOptions::validate() const {
  if (folds < 2)
    throw std::invalid_argument("SelectionOptions: folds = " + std::to_string(folds) +
                                " must be >= 2");
  if (max_terms < 0)
    throw std::invalid_argument("SelectionOptions: max_terms must be >= 0");
  if (!(max_rho > 0.0 && max_rho < 1.0))
    throw std::invalid_argument("SelectionOptions: max_rho must be in (0, 1)");
  if (!(replay_period_s >= 0.0) || !(bin_s >= 0.0))
    throw std::invalid_argument("SelectionOptions: replay_period_s and bin_s must be >= 0");
  if (!(min_name_margin >= 0.0))
    throw std::invalid_argument("SelectionOptions: min_name_margin must be >= 0");
}

namespace {

// Gram matrices of the whitened problem, per fold.
struct GramSet {
  std::vector<Eigen::MatrixXd> G;  // per fold
  std::vector<Eigen::VectorXd> b;
  std::vector<double> yy;
  Eigen::MatrixXd G_all;
  Eigen::VectorXd b_all;
  double yy_all = 0.0;
  int rows = 0;
};

struct ColumnMap {
  std::vector<int> start, count;
  int total = 0;
};

ColumnMap mapColumns(const std::vector<CandidateTerm>& terms) {
  ColumnMap m;
  for (const CandidateTerm& t : terms) {
    m.start.push_back(m.total);
    m.count.push_back(static_cast<int>(t.columns.size()));
    m.total += static_cast<int>(t.columns.size());
  }
  return m;
}

// Row i (from rb) of z prewhitened by AR(1) rho and scaled by w; the first row keeps the
// stationary variance (sqrt(1 - rho^2)).
double whitenedRow(const Eigen::VectorXd& z, int rb, int i, double rho, double w) {
  const int t = rb + i;
  return i == 0 ? w * std::sqrt(std::max(0.0, 1.0 - rho * rho)) * z(t)
                : w * (z(t) - rho * z(t - 1));
}

// The candidate columns acting on channel c: their global indices and their series there.
struct ChannelColumns {
  std::vector<int> idx;
  std::vector<const Eigen::VectorXd*> src;
};
ChannelColumns channelColumns(const std::vector<CandidateTerm>& terms, const ColumnMap& map,
                              int c) {
  ChannelColumns out;
  for (std::size_t t = 0; t < terms.size(); ++t)
    for (int j = 0; j < map.count[t]; ++j)
      if (terms[t].columns[j].actsOn(c)) {
        out.idx.push_back(map.start[t] + j);
        out.src.push_back(&terms[t].columns[j].channel[c]);
      }
  return out;
}

// The series `src`, and `last` as one more column when given, whitened over `len` rows from
// row rb (whitenedRow): the rows the fit sees.
Eigen::MatrixXd whitenedColumns(const std::vector<const Eigen::VectorXd*>& src,
                                const Eigen::VectorXd* last, int rb, int len, double rho,
                                double w) {
  const int m = static_cast<int>(src.size());
  Eigen::MatrixXd X(len, m + (last ? 1 : 0));
  for (int i = 0; i < len; ++i) {
    for (int k = 0; k < m; ++k) X(i, k) = whitenedRow(*src[k], rb, i, rho, w);
    if (last) X(i, m) = whitenedRow(*last, rb, i, rho, w);
  }
  return X;
}

// First row of CV fold f of `folds` contiguous folds over `len` rows (fold f is
// [foldStart(f), foldStart(f + 1))): the one partition the white and the GLS fold grams share.
int foldStart(int len, int f, int folds) {
  return static_cast<int>(static_cast<long>(len) * f / folds);
}

GramSet accumulate(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                   const ColumnMap& map, const Eigen::Matrix<double, 6, 1>& rho,
                   const Eigen::Matrix<double, 6, 1>& weight, int rb, int re, int folds) {
  GramSet g;
  const int P = map.total;
  g.G.assign(folds, Eigen::MatrixXd::Zero(P, P));
  g.b.assign(folds, Eigen::VectorXd::Zero(P));
  g.yy.assign(folds, 0.0);
  const int len = re - rb;
  for (int c = 0; c < kMismatchChannels; ++c) {
    const ChannelColumns cols = channelColumns(terms, map, c);
    const std::vector<int>& idx = cols.idx;
    const int m = static_cast<int>(idx.size());
    const Eigen::VectorXd rc = r.col(c);
    const Eigen::MatrixXd Xy = whitenedColumns(cols.src, &rc, rb, len, rho(c), weight(c));
    for (int f = 0; f < folds; ++f) {
      const int a = foldStart(len, f, folds), b = foldStart(len, f + 1, folds);
      const auto Xf = Xy.leftCols(m).middleRows(a, b - a);
      const auto yf = Xy.col(m).segment(a, b - a);
      const Eigen::MatrixXd Gf = Xf.transpose() * Xf;
      const Eigen::VectorXd bf = Xf.transpose() * yf;
      for (int j = 0; j < m; ++j) {
        g.b[f](idx[j]) += bf(j);
        for (int k = 0; k < m; ++k) g.G[f](idx[j], idx[k]) += Gf(j, k);
      }
      g.yy[f] += yf.squaredNorm();
    }
    g.rows += len;
  }
  g.G_all = Eigen::MatrixXd::Zero(P, P);
  g.b_all = Eigen::VectorXd::Zero(P);
  for (int f = 0; f < folds; ++f) {
    g.G_all += g.G[f];
    g.b_all += g.b[f];
    g.yy_all += g.yy[f];
  }
  return g;
}

struct ModelFit {
  std::vector<int> free_cols, fixed_cols;
  Eigen::VectorXd theta;
  Eigen::MatrixXd A_inv;
  std::vector<bool> unobservable;  // free columns with no signal (e.g. max(x, 0) of a negative x)
  double rss = 0.0;
};

// Columns of a set of terms.
void modelColumns(const std::vector<int>& model, const std::vector<CandidateTerm>& terms,
                  const ColumnMap& map, std::vector<int>* free_cols, std::vector<int>* fixed_cols) {
  free_cols->clear();
  fixed_cols->clear();
  for (int t : model)
    for (int j = 0; j < map.count[t]; ++j)
      (terms[t].fixed ? fixed_cols : free_cols)->push_back(map.start[t] + j);
}

// A normal matrix made safely invertible: a relative ridge of 1e-11, and all-zero columns (no
// signal: theta 0, sigma infinite) pinned; `pinned`, when given, marks them.
Eigen::MatrixXd regularized(const Eigen::MatrixXd& A, std::vector<bool>* pinned = nullptr) {
  Eigen::MatrixXd Ar = A;
  if (pinned) pinned->assign(A.rows(), false);
  if (A.rows() == 0) return Ar;
  const double diag_max = std::max(A.diagonal().maxCoeff(), 1e-300);
  Ar.diagonal().array() += 1e-11 * diag_max;
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    if (A(i, i) <= 1e-14 * diag_max) {
      Ar(i, i) += diag_max;
      if (pinned) (*pinned)[i] = true;
    }
  return Ar;
}

// Least squares on G, b, yy with the fixed columns' coefficients at 1.
ModelFit solve(const Eigen::MatrixXd& G, const Eigen::VectorXd& b, double yy,
               const std::vector<int>& S, const std::vector<int>& F, bool want_inverse) {
  ModelFit fit;
  fit.free_cols = S;
  fit.fixed_cols = F;
  const int p = static_cast<int>(S.size());
  double zz = yy;
  for (int i : F) {
    zz -= 2.0 * b(i);
    for (int j : F) zz += G(i, j);
  }
  Eigen::VectorXd Xz(p);
  Eigen::MatrixXd A(p, p);
  for (int i = 0; i < p; ++i) {
    Xz(i) = b(S[i]);
    for (int j : F) Xz(i) -= G(S[i], j);
    for (int j = 0; j < p; ++j) A(i, j) = G(S[i], S[j]);
  }
  if (p == 0) {
    fit.rss = zz;
    return fit;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(regularized(A, &fit.unobservable));
  fit.theta = ldlt.solve(Xz);
  fit.rss = zz - 2.0 * fit.theta.dot(Xz) + fit.theta.dot(A * fit.theta);
  if (want_inverse) fit.A_inv = ldlt.solve(Eigen::MatrixXd::Identity(p, p));
  return fit;
}

// Whitened squared prediction error of theta (over S, fixed F at 1) on one fold's Gram.
double foldError(const ModelFit& fit, const Eigen::MatrixXd& G, const Eigen::VectorXd& b, double yy) {
  // e = z - X theta with z = y - X_F 1:  |e|^2 = zz - 2 theta' X'z + theta' X'X theta.
  const auto& S = fit.free_cols;
  const auto& F = fit.fixed_cols;
  double zz = yy;
  for (int i : F) {
    zz -= 2.0 * b(i);
    for (int j : F) zz += G(i, j);
  }
  double cross = 0.0, quad = 0.0;
  for (std::size_t i = 0; i < S.size(); ++i) {
    double xz = b(S[i]);
    for (int j : F) xz -= G(S[i], j);
    cross += fit.theta(i) * xz;
    for (std::size_t j = 0; j < S.size(); ++j) quad += fit.theta(i) * G(S[i], S[j]) * fit.theta(j);
  }
  return zz - 2.0 * cross + quad;
}

}  // namespace

Eigen::MatrixXd atLeastTheVariances(const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q) {
  if (P.rows() != P.cols() || Q.rows() != P.rows() || Q.cols() != P.cols())
    throw std::invalid_argument("atLeastTheVariances: P and Q must be square and of one size");
  Eigen::VectorXd d = Eigen::VectorXd::Ones(P.rows());
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (Q(i, i) > P(i, i)) d(i) = P(i, i) > 0.0 ? std::sqrt(Q(i, i) / P(i, i)) : 1.0;
  Eigen::MatrixXd out = d.asDiagonal() * P * d.asDiagonal();
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (!(P(i, i) > 0.0) && Q(i, i) > P(i, i)) out(i, i) = Q(i, i);
  return out;
}

namespace {

class Selector {
 public:
  Selector(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
           const SelectionOptions& opt, int rb, int re)
      : terms_(terms), opt_(opt), map_(mapColumns(terms)), r_(r), rb_(rb), re_(re) {
    // Noise model from the largest model: all candidates, one of each exclusive group.
    std::vector<int> full = {0};
    for (std::size_t t = 1; t < terms.size(); ++t) {
      if (terms[t].fixed || terms[t].gauge_only) continue;
      full = withRequired(full, static_cast<int>(t));
    }
    Eigen::Matrix<double, 6, 1> w0, zero = Eigen::Matrix<double, 6, 1>::Zero();
    for (int c = 0; c < kMismatchChannels; ++c) {
      const Eigen::VectorXd col = r.col(c).segment(rb, re - rb);
      const double mean = col.mean();
      const double sd = std::sqrt((col.array() - mean).square().mean());
      w0(c) = sd > 0.0 ? 1.0 / sd : 1.0;
    }
    {
      const GramSet g0 = accumulate(r, terms, map_, zero, w0, rb, re, opt.folds);
      std::vector<int> S, F;
      modelColumns(full, terms, map_, &S, &F);
      const ModelFit f0 = solve(g0.G_all, g0.b_all, g0.yy_all, S, F, false);
      const Eigen::MatrixXd e = residualOf(r, full, f0, rb, re);
      for (int c = 0; c < kMismatchChannels; ++c) {
        const Eigen::VectorXd ec = e.col(c);
        const double den = ec.squaredNorm();
        double p = den > 0.0 ? ec.head(ec.size() - 1).dot(ec.tail(ec.size() - 1)) / den : 0.0;
        p = std::clamp(p, 0.0, opt.max_rho);
        rho_(c) = p;
        const Eigen::VectorXd innov = ec.tail(ec.size() - 1) - p * ec.head(ec.size() - 1);
        const double s = std::sqrt(innov.squaredNorm() / std::max<Eigen::Index>(1, innov.size()));
        sigma_(c) = s > 0.0 ? s : 1.0;
      }
    }
    Eigen::Matrix<double, 6, 1> w = sigma_.cwiseInverse();
    gram_ = accumulate(r, terms, map_, rho_, w, rb, re, opt.folds);
    // Residual correlation the AR(1) model leaves: variance inflation.
    {
      std::vector<int> S, F;
      modelColumns(full, terms, map_, &S, &F);
      const ModelFit f1 = solve(gram_.G_all, gram_.b_all, gram_.yy_all, S, F, false);
      const Eigen::MatrixXd e = residualOf(r, full, f1, rb, re);
      double num = 0.0, den = 0.0;
      for (int c = 0; c < kMismatchChannels; ++c) {
        Eigen::VectorXd ew(e.rows() - 1);
        for (Eigen::Index i = 1; i < e.rows(); ++i) ew(i - 1) = (e(i, c) - rho_(c) * e(i - 1, c)) / sigma_(c);
        num += ew.head(ew.size() - 1).dot(ew.tail(ew.size() - 1));
        den += ew.squaredNorm();
      }
      const double pw = den > 0.0 ? std::clamp(num / den, 0.0, 0.95) : 0.0;
      inflation_ = (1.0 + pw) / (1.0 - pw);
      // The full model's whitened residual variance also scales the evidence when above 1.
      const double var = f1.rss / std::max(1.0, gram_.rows - static_cast<double>(S.size()));
      inflation_ *= std::max(1.0, var);
    }
    full_ = full;
    priorVariances();
  }

  // The prior of step 2: isotropic within a term (its parameters share units), with the variance
  // that makes the information of the term's average column, net of the nuisance, worth N / c
  // observations ("unit information"): prior variance = (N / c) p / trace(D), D the whitened
  // normal matrix of the term's columns with the nuisance projected out, p its columns with
  // signal. A term whose columns are equally informative and orthogonal to the base gets
  // s_i = N / c on every direction, the BIC penalty ln(1 + N / c) per parameter.
  void priorVariances() {
    prior_variance_.assign(terms_.size(), 0.0);
    column_prior_variance_.assign(map_.total, 0.0);
    const double n_eff = gram_.rows / inflation_;
    const Eigen::MatrixXd& G = gram_.G_all;
    std::vector<int> Sn, Fn;
    modelColumns({0}, terms_, map_, &Sn, &Fn);
    const int pn = static_cast<int>(Sn.size());
    Eigen::MatrixXd Gnn(pn, pn);
    for (int i = 0; i < pn; ++i)
      for (int j = 0; j < pn; ++j) Gnn(i, j) = G(Sn[i], Sn[j]);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(regularized(Gnn));
    for (std::size_t t = 1; t < terms_.size(); ++t) {
      if (terms_[t].fixed) continue;
      const int k = map_.count[t];
      Eigen::MatrixXd Ctn(k, pn);
      Eigen::VectorXd d(k);
      for (int i = 0; i < k; ++i) {
        d(i) = G(map_.start[t] + i, map_.start[t] + i);
        for (int j = 0; j < pn; ++j) Ctn(i, j) = G(map_.start[t] + i, Sn[j]);
      }
      const Eigen::MatrixXd proj = Ctn * ldlt.solve(Ctn.transpose());
      const double dmax = d.maxCoeff();
      double trace = 0.0;
      int live = 0;
      for (int i = 0; i < k; ++i) {
        if (!(d(i) > 1e-14 * dmax)) continue;  // a column without signal
        const double net = std::max(0.0, d(i) - proj(i, i));
        trace += net;
        ++live;
        if (net > 0.0) column_prior_variance_[map_.start[t] + i] = n_eff / net;
      }
      if (trace > 0.0) prior_variance_[t] = n_eff * live / trace;
    }
  }

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

  bool isSlow(int t) const {
    const std::string& nm = terms_[t].name;
    return nm == "bias_instability" || nm == "temperature_bias" || nm == "temperature_scale" ||
           nm == "gravity_model" || nm == "earth_rotation_omitted";
  }

  // `for_slow_term`: the noise a slow term is measured against (blockMeanNoise).
  const SlowNoise& slowNoise(const std::vector<int>& base, bool for_slow_term = false) const {
    std::vector<int> slow_in_base;
    for (int t : base)
      if (isSlow(t)) slow_in_base.push_back(t);
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

  // Whitened series (AR(1) of channel c, divided by its innovation scale) over the selection
  // rows, mean removed (the nuisance constant), as the fit sees it.
  Eigen::VectorXd whitened(const Eigen::VectorXd& z, int c, int offset) const {
    const int len = re_ - rb_;
    Eigen::VectorXd w(len);
    for (int i = 0; i < len; ++i) {
      const double prev = i > 0 ? z(offset + i - 1) : 0.0;
      w(i) = (z(offset + i) - (i > 0 ? rho_(c) * prev : 0.0)) / sigma_(c);
    }
    w.array() -= w.mean();
    return w;
  }

  // Per channel, the level-j parts of the normal equations of the whitened rows (as accumulate
  // builds them) of the columns acting on it: [X y]' [X y] of the Haar level-j coefficients.
  struct ChannelLevels {
    std::vector<int> idx;                // global column indices
    std::vector<Eigen::MatrixXd> gram;   // per Haar level, (m + 1) x (m + 1), y last
    // Per CV fold (the folds of accumulate), its rows transformed on their own, per level.
    std::vector<std::vector<Eigen::MatrixXd>> fold_gram;
  };
  const std::array<ChannelLevels, kMismatchChannels>& levelGrams() const {
    if (!level_grams_) {
      level_grams_ = std::make_unique<std::array<ChannelLevels, kMismatchChannels>>();
      const int len = re_ - rb_;
      for (int c = 0; c < kMismatchChannels; ++c) {
        ChannelLevels& cl = (*level_grams_)[c];
        ChannelColumns cols = channelColumns(terms_, map_, c);
        cl.idx = std::move(cols.idx);
        const Eigen::VectorXd rc = r_.col(c);
        const Eigen::MatrixXd Xy =
            whitenedColumns(cols.src, &rc, rb_, len, rho_(c), 1.0 / sigma_(c));
        for (const Eigen::MatrixXd& D : haarCoefficients(Xy)) cl.gram.push_back(D.transpose() * D);
        const int folds = static_cast<int>(gram_.G.size());
        cl.fold_gram.resize(folds);
        for (int f = 0; f < folds; ++f) {
          const int a = foldStart(len, f, folds), b = foldStart(len, f + 1, folds);
          for (const Eigen::MatrixXd& D : haarCoefficients(Xy.middleRows(a, b - a)))
            cl.fold_gram[f].push_back(D.transpose() * D);
        }
      }
    }
    return *level_grams_;
  }

  // The residual of the fast model plus the slow terms `slow_in_model` (whitened, mean removed).
  Eigen::MatrixXd slowResidual(const std::vector<int>& slow_in_model) const {
    std::vector<int> fast;
    for (int t : full_)
      if (!isSlow(t)) fast.push_back(t);
    for (int t : slow_in_model) fast = withTerm(fast, t);
    std::vector<int> S, F;
    modelColumns(fast, terms_, map_, &S, &F);
    const ModelFit fit = solve(gram_.G_all, gram_.b_all, gram_.yy_all, S, F, false);
    const Eigen::MatrixXd e = residualOf(r_, fast, fit, rb_, re_);
    Eigen::MatrixXd w(e.rows(), e.cols());
    for (int c = 0; c < kMismatchChannels; ++c) w.col(c) = whitened(e.col(c), c, 0);
    return w;
  }

  // The AR(1)-whitened normal equations as they are (no slow-noise weighting, factors 1).
  SlowNoise whiteNoise() const {
    SlowNoise out;
    out.G = gram_.G_all;
    out.b = gram_.b_all;
    out.yy = gram_.yy_all;
    out.G_fold = gram_.G;
    out.b_fold = gram_.b;
    out.yy_fold = gram_.yy;
    out.term_inflation.assign(terms_.size(), 1.0);
    return out;
  }

  // Whole slow-noise blocks in the fitted rows (0 when the check is off).
  int slowBlocks() const {
    const int m = opt_.slow_block_bins;
    return m > 1 ? (re_ - rb_) / m : 0;
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
  SlowNoise blockMeanNoise() const {
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
          std::max(1.0, blockEnergy(blockMeans(e.col(c))) / blocks / inflation_);
    // The two realizations' unit covariance: the field's walk, plus the lab's replayed one when
    // the simulation is SG#2 (block b starts rb_ + b m bins into the grid).
    Eigen::MatrixXd K = blockRandomWalkCovariance(blocks);
    if (opt_.replay_period_s > 0.0 && opt_.bin_s > 0.0) {
      ReplayTiling tiling;
      tiling.period_s = opt_.replay_period_s;
      tiling.block_s = m * opt_.bin_s;
      tiling.start_s = opt_.replay_start_s + rb_ * opt_.bin_s;
      K += replayedRandomWalkCovariance(blocks, tiling);
    }
    for (std::size_t t = 0; t < terms_.size(); ++t) {
      double num = 0.0, num_walk = 0.0, total = 0.0;
      std::optional<Eigen::MatrixXd> own_residual;
      // Per sensor triad (gyro channels 0-2, accel 3-5): the term's whitened columns on each
      // channel as block means, and that channel's residual block means.
      for (int sensor = 0; sensor < 2; ++sensor) {
        std::vector<std::vector<Eigen::VectorXd>> means(3);
        for (int k = 0; k < 3; ++k) {
          const int c = 3 * sensor + k;
          for (const RegressorColumn& col : terms_[t].columns) {
            if (!col.actsOn(c)) continue;
            const Eigen::VectorXd w = whitened(col.channel[c], c, rb_);
            const double energy = w.squaredNorm();
            means[k].push_back(blockMeans(w));
            num += std::min(blockEnergy(means[k].back()), energy) * (out.slow_inflation(c) - 1.0);
            total += energy;
          }
        }
        if (!isSlow(static_cast<int>(t))) continue;
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
          ys.push_back(blockMeans(own_residual->col(3 * sensor + k)));
          Xs.push_back(std::move(X));
        }
        if (ys.empty()) continue;
        const double q = remlBlockRandomWalk(ys, Xs, inflation_ / m, K);
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

  SlowNoise estimateSlowNoise(const std::vector<int>& slow_in_model) const {
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
    const int P = map_.total;
    out.G = Eigen::MatrixXd::Zero(P, P);
    out.b = Eigen::VectorXd::Zero(P);
    out.yy = 0.0;
    const int folds = static_cast<int>(gram_.G.size());
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
          fitScaleNoise(haarEnergies(e.col(c)), inflation_, report_level + 1);
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
  Eigen::MatrixXd randomWalkMeat(const SlowNoise& sn, const std::vector<int>& S) const {
    const int p = static_cast<int>(S.size());
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(p, p);
    const int len = re_ - rb_;
    for (int c = 0; c < kMismatchChannels; ++c) {
      const ChannelColumns all = channelColumns(terms_, map_, c);
      std::vector<int> pos;  // the free columns on channel c: their places in S
      std::vector<const Eigen::VectorXd*> src;
      for (std::size_t k = 0; k < all.idx.size(); ++k) {
        const auto it = std::find(S.begin(), S.end(), all.idx[k]);
        if (it == S.end()) continue;
        pos.push_back(static_cast<int>(it - S.begin()));
        src.push_back(all.src[k]);
      }
      const int m = static_cast<int>(src.size());
      if (m == 0) continue;
      std::vector<Eigen::MatrixXd> levels =
          haarCoefficients(whitenedColumns(src, nullptr, rb_, len, rho_(c), 1.0 / sigma_(c)));
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

  // Step 4's gauge. The antisymmetric parts of the two full non-orthogonalities span a rotation
  // common to both triads, which mounting_misalignment spans as well: with all three in a model
  // the split is arbitrary, and with both N the misalignment fails its own test (no evidence
  // left) and is dropped, so one physical rotation was named as two cross-axis matrices
  // depending on the order of selection (wid_car_trial07; the CRN misalignment case). A final
  // model with both full N is re-expressed as mounting_misalignment + gyro N + the
  // accelerometer's symmetric N: the same span and fit, evidence measured per name.
  std::vector<int> gaugeFixed(std::vector<int> model, std::vector<std::string>* log) const {
    const int ng = indexOf("non_orthogonality:gyro"), na = indexOf("non_orthogonality:accel"),
              na_sym = indexOf("non_orthogonality:accel:symmetric"),
              rot = indexOf("mounting_misalignment:both");
    const auto has = [&](int t) { return std::find(model.begin(), model.end(), t) != model.end(); };
    if (ng < 0 || na < 0 || na_sym < 0 || rot < 0 || !has(ng) || !has(na)) return model;
    model.erase(std::remove(model.begin(), model.end(), na), model.end());
    if (!has(rot)) model = withRequired(model, rot);
    model.push_back(na_sym);
    std::sort(model.begin(), model.end());
    log->push_back("gauge: both non_orthogonality terms re-expressed as mounting_misalignment + "
                   "non_orthogonality:gyro + non_orthogonality:accel:symmetric (same fit)");
    return model;
  }

  int indexOf(const std::string& key) const {
    for (std::size_t k = 0; k < terms_.size(); ++k)
      if (terms_[k].key() == key) return static_cast<int>(k);
    return -1;
  }

  // The model a term is tested against: the current one plus the terms it requires.
  std::vector<int> baseFor(const std::vector<int>& model, int t) const {
    std::vector<int> base = model;
    for (const std::string& req : terms_[t].requires_terms) {
      const int k = indexOf(req);
      if (k >= 0) base = withTerm(base, k);
    }
    return base;
  }

  // The model with t and the terms t requires.
  std::vector<int> withRequired(const std::vector<int>& model, int t) const {
    return withTerm(baseFor(model, t), t);
  }

  bool requiredByOthers(const std::vector<int>& model, int t) const {
    for (int m : model)
      for (const std::string& req : terms_[m].requires_terms)
        if (req == terms_[t].key()) return true;
    return false;
  }

  std::vector<int> withTerm(std::vector<int> model, int t) const {
    for (const std::string& ex : terms_[t].excludes)  // with its parts
      model.erase(std::remove_if(model.begin(), model.end(),
                                 [&](int m) {
                                   return terms_[m].key() == ex || terms_[m].part_of == ex;
                                 }),
                  model.end());
    for (int m : model)  // a term that excludes t keeps t out
      for (const std::string& ex : terms_[m].excludes)
        if (ex == terms_[t].key()) return model;
    if (std::find(model.begin(), model.end(), t) == model.end()) model.push_back(t);
    std::sort(model.begin(), model.end());
    return model;
  }

  // The model without t. A term t replaced (excludes) is not brought back: it is an alternative
  // explanation, which forward selection offers again after any drop. Restoring it here made
  // backward elimination cycle between two alternatives of equal evidence, each failing against
  // the other.
  // The parts of t (part_of) leave with it.
  std::vector<int> withoutTerm(std::vector<int> model, int t) const {
    model.erase(std::remove_if(model.begin(), model.end(),
                               [&](int m) { return m == t || terms_[m].part_of == terms_[t].key(); }),
                model.end());
    return model;
  }

  // A model without the parts whose term is not in it (e.g. after a gate took the term out).
  std::vector<int> withoutOrphanParts(std::vector<int> model) const {
    const std::vector<int> in = model;
    model.erase(std::remove_if(model.begin(), model.end(),
                               [&](int m) {
                                 if (terms_[m].part_of.empty()) return false;
                                 return std::none_of(in.begin(), in.end(), [&](int o) {
                                   return terms_[o].key() == terms_[m].part_of;
                                 });
                               }),
                model.end());
    return model;
  }

  // Evidence of going from `without` to `with` for term t: twice the log Bayes factor of the
  // two models (header, step 2). With a term that replaces another (excludes) the models are not
  // nested; both are then measured against the terms they share.
  // `column_prior`: the added columns under their own priors (step 5's names).
  double deltaBic(const std::vector<int>& without, const std::vector<int>& with, int t,
                  bool column_prior = false) const {
    const SlowNoise& sn = slowNoiseFor(t, without);
    std::vector<int> common;
    std::set_intersection(without.begin(), without.end(), with.begin(), with.end(),
                          std::back_inserter(common));
    const double c = inflation_ * sn.term_inflation[t];
    double e = evidenceOver(common, with, sn, c, column_prior);
    if (common != without) e -= evidenceOver(common, without, sn, c, column_prior);
    return e;
  }

  // Information of the columns a model adds to a base model, the base projected out: what the
  // Laplace evidence and the detection limit are computed from.
  struct AddedInformation {
    std::vector<int> Sb, Fb, Sa, Fa, F;  // free / fixed columns of the base and of the added terms
    Eigen::MatrixXd A;                   // information of the added free columns, base projected out
    Eigen::VectorXd r;                   // their score (whitened X'y net of the fixed columns)
    Eigen::VectorXd sd;                  // prior standard deviation per added free column
  };

  // `column_prior`: each added column under its own unit-information prior (step 5) instead of
  // its term's isotropic one.
  AddedInformation addedInformation(const std::vector<int>& base, const std::vector<int>& model,
                                    const SlowNoise& sn, bool column_prior = false) const {
    AddedInformation ai;
    std::vector<int> added;
    std::set_difference(model.begin(), model.end(), base.begin(), base.end(),
                        std::back_inserter(added));
    modelColumns(base, terms_, map_, &ai.Sb, &ai.Fb);
    modelColumns(added, terms_, map_, &ai.Sa, &ai.Fa);
    ai.F = ai.Fb;
    ai.F.insert(ai.F.end(), ai.Fa.begin(), ai.Fa.end());
    const int pa = static_cast<int>(ai.Sa.size());
    if (pa == 0) return ai;
    const Eigen::MatrixXd& G = sn.G;
    auto target = [&](int i) {
      double v = sn.b(i);
      for (int j : ai.F) v -= G(i, j);
      return v;
    };
    ai.A.resize(pa, pa);
    ai.r.resize(pa);
    for (int i = 0; i < pa; ++i) {
      ai.r(i) = target(ai.Sa[i]);
      for (int j = 0; j < pa; ++j) ai.A(i, j) = G(ai.Sa[i], ai.Sa[j]);
    }
    const int pb = static_cast<int>(ai.Sb.size());
    if (pb > 0) {
      Eigen::MatrixXd Bb(pb, pb), Cab(pa, pb);
      Eigen::VectorXd rb(pb);
      for (int i = 0; i < pb; ++i) {
        rb(i) = target(ai.Sb[i]);
        for (int j = 0; j < pb; ++j) Bb(i, j) = G(ai.Sb[i], ai.Sb[j]);
      }
      for (int i = 0; i < pa; ++i)
        for (int j = 0; j < pb; ++j) Cab(i, j) = G(ai.Sa[i], ai.Sb[j]);
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(regularized(Bb));
      ai.A -= Cab * ldlt.solve(Cab.transpose());
      ai.r -= Cab * ldlt.solve(rb);
    }
    ai.sd = Eigen::VectorXd::Zero(pa);
    for (int t : added) {
      if (terms_[t].fixed) continue;
      for (int j = 0; j < map_.count[t]; ++j) {
        const int col = map_.start[t] + j;
        const int i = static_cast<int>(std::find(ai.Sa.begin(), ai.Sa.end(), col) - ai.Sa.begin());
        ai.sd(i) = std::sqrt(column_prior ? column_prior_variance_[col] : prior_variance_[t]);
      }
    }
    return ai;
  }

  // Eigen-decomposition of the prior-scaled information sd A sd, eigenvalues floored.
  static Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> scaledInformation(const AddedInformation& ai,
                                                                         Eigen::VectorXd* s) {
    const Eigen::MatrixXd M = ai.sd.asDiagonal() * ai.A * ai.sd.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (M + M.transpose()));
    const double smax = std::max(eig.eigenvalues().maxCoeff(), 0.0);
    *s = eig.eigenvalues().cwiseMax(1e-12 * smax);
    return eig;
  }

  // 2 ln(Bayes factor) of `model` over `base` (a subset of it), Laplace form with a Gaussian prior
  // on the added parameters: sum_i [q_i s_i / (1 + s_i) - ln(1 + s_i)] over the eigen-directions
  // i of the added parameters' information after projecting out the base, q_i the RSS drop along
  // direction i (divided by the AR(1) leftover c) and s_i = prior variance x information there,
  // both from the GLS normal equations of the slow noise `sn`. Added fixed terms contribute their
  // RSS drop divided by c, without a penalty.
  double evidenceOver(const std::vector<int>& base, const std::vector<int>& model,
                      const SlowNoise& sn, double c, bool column_prior = false) const {
    const AddedInformation ai = addedInformation(base, model, sn, column_prior);
    double gain = 0.0;
    if (!ai.Fa.empty())
      gain += (solve(sn.G, sn.b, sn.yy, ai.Sb, ai.Fb, false).rss -
               solve(sn.G, sn.b, sn.yy, ai.Sb, ai.F, false).rss) / c;
    const int pa = static_cast<int>(ai.Sa.size());
    if (pa == 0) return gain;
    Eigen::VectorXd s;
    const auto eig = scaledInformation(ai, &s);
    const Eigen::VectorXd h = eig.eigenvectors().transpose() * ai.sd.cwiseProduct(ai.r);
    for (int i = 0; i < pa; ++i) {
      // q s / (1 + s) with q = h^2 / (s c): the drop along the direction, shrunk by the prior.
      gain += h(i) * h(i) / (c * (1.0 + s(i))) - std::log1p(s(i));
    }
    return gain;
  }

  // Detection limit of term t (not in `model`) per column: the value that column alone (the
  // term's others zero) must have for its noise-free evidence over `model` to reach
  // min_delta_bic: with score A theta e_j the gain is theta^2 Q_j - P, P = sum ln(1 + s_i),
  // Q_j = sum_i (V' sd A e_j)_i^2 / (c (1 + s_i)). About a 50 % detection probability; infinite
  // for a column with no information.
  Eigen::VectorXd detectionLimit(const std::vector<int>& model, int t) const {
    const int k = map_.count[t];
    Eigen::VectorXd limit = Eigen::VectorXd::Constant(k, std::numeric_limits<double>::infinity());
    const std::vector<int> base = baseFor(model, t);
    const std::vector<int> with = withTerm(base, t);
    if (with == base || terms_[t].fixed || terms_[t].nuisance) return limit;
    std::vector<int> common;
    std::set_intersection(base.begin(), base.end(), with.begin(), with.end(),
                          std::back_inserter(common));
    const SlowNoise& sn = slowNoiseFor(t, base);
    const AddedInformation ai = addedInformation(common, with, sn);
    if (ai.Sa.empty()) return limit;
    const double c = inflation_ * sn.term_inflation[t];
    Eigen::VectorXd s;
    const auto eig = scaledInformation(ai, &s);
    double P = 0.0;
    for (int i = 0; i < s.size(); ++i) P += std::log1p(s(i));
    for (int j = 0; j < k; ++j) {
      const int col = map_.start[t] + j;
      const auto it = std::find(ai.Sa.begin(), ai.Sa.end(), col);
      if (it == ai.Sa.end()) continue;
      const int i = static_cast<int>(it - ai.Sa.begin());
      const Eigen::VectorXd h = eig.eigenvectors().transpose() * ai.sd.cwiseProduct(ai.A.col(i));
      double Q = 0.0;
      for (int m = 0; m < s.size(); ++m) Q += h(m) * h(m) / (c * (1.0 + s(m)));
      if (Q > 0.0) limit(j) = std::sqrt((P + opt_.min_delta_bic) / Q);
    }
    return limit;
  }

  // The slow noise term t is tested against, with the model `base` (which does not hold t).
  const SlowNoise& slowNoiseFor(int t, const std::vector<int>& base) const {
    return isSlow(t) ? slowNoise({}, true) : slowNoise(base);
  }
  // Blocked CV error of `model` in the metric of the noise `sn` (the slow noise the term under
  // test is measured against: GLS per fold for a fast term, white for a slow one).
  double cvError(const std::vector<int>& model, const SlowNoise& sn) const {
    const auto key = std::make_pair(&sn, model);
    const auto it = cv_cache_.find(key);
    if (it != cv_cache_.end()) return it->second;
    std::vector<int> S, F;
    modelColumns(model, terms_, map_, &S, &F);
    Eigen::MatrixXd G_sum = Eigen::MatrixXd::Zero(map_.total, map_.total);
    Eigen::VectorXd b_sum = Eigen::VectorXd::Zero(map_.total);
    double yy_sum = 0.0;
    for (int f = 0; f < opt_.folds; ++f) {
      G_sum += sn.G_fold[f];
      b_sum += sn.b_fold[f];
      yy_sum += sn.yy_fold[f];
    }
    double cv = 0.0;
    for (int f = 0; f < opt_.folds; ++f) {
      const ModelFit tr = solve(G_sum - sn.G_fold[f], b_sum - sn.b_fold[f],
                                yy_sum - sn.yy_fold[f], S, F, false);
      cv += foldError(tr, sn.G_fold[f], sn.b_fold[f], sn.yy_fold[f]);
    }
    cv_cache_.emplace(key, cv);
    return cv;
  }

  // Relative CV improvement of `with` over `without` for term t, in t's noise metric.
  double cvGain(const std::vector<int>& without, const std::vector<int>& with, int t) const {
    const SlowNoise& sn = slowNoiseFor(t, without);
    const double ref = cvError(without, sn);
    return ref > 0.0 ? (ref - cvError(with, sn)) / ref : 0.0;
  }

  void evidence(const std::vector<int>& model, int t, double* delta_bic, double* cv_gain) const {
    const std::vector<int> base = withoutTerm(model, t);
    *delta_bic = deltaBic(base, model, t);
    *cv_gain = cvGain(base, model, t);
  }

  bool passes(double delta_bic, double cv_gain) const {
    return delta_bic > opt_.min_delta_bic && cv_gain > opt_.min_cv_gain;
  }

  // Step 5: the evidence of term t (in `model`) over its best shape alternative, the model with
  // that alternative (and what it requires) in t's place, each added column under the
  // unit-information prior of that column alone; and the alternative's index (-1: none applies,
  // e.g. both shapes are in the model and each was measured against the other).
  std::pair<double, int> nameMargin(const std::vector<int>& model, int t) const {
    std::pair<double, int> best{std::numeric_limits<double>::infinity(), -1};
    const std::vector<std::string>& names = terms_[t].shape_alternatives;
    if (names.empty()) return best;
    const std::vector<int> without = withoutTerm(model, t);
    for (std::size_t u = 1; u < terms_.size(); ++u) {
      const CandidateTerm& cu = terms_[u];
      const int ui = static_cast<int>(u);
      if (cu.sensor != terms_[t].sensor || cu.nuisance || cu.fixed || cu.gauge_only ||
          !cu.part_of.empty() || std::find(names.begin(), names.end(), cu.name) == names.end() ||
          std::find(model.begin(), model.end(), ui) != model.end())
        continue;
      const std::vector<int> alternative = withRequired(without, ui);
      if (alternative == without) continue;
      const double margin = deltaBic(alternative, model, t, /*column_prior=*/true);
      if (margin < best.first) best = {margin, ui};
    }
    return best;
  }

  SelectionResult result(const std::vector<int>& model) const {
    SelectionResult res;
    res.rho = rho_;
    res.sigma = sigma_;
    res.inflation = inflation_;
    res.slow_inflation = slowNoise(model).slow_inflation;
    res.rows = gram_.rows;
    std::vector<int> S, F;
    modelColumns(model, terms_, map_, &S, &F);
    // Each term's estimate and covariance come from the GLS of the slow noise it is measured
    // against (a slow term: without any slow term; a fast one: with the model's slow terms).
    // Whitened noise has unit variance; the inflation c carries the leftover correlation and any
    // excess variance of the full model's residual.
    std::map<const SlowNoise*, ModelFit> fits;
    std::map<const SlowNoise*, Eigen::MatrixXd> sandwich;  // random_walk_sandwich covariances
    int pos = 0;
    for (int t : model) {
      TermFit tf;
      tf.term = t;
      const int k = map_.count[t];
      if (terms_[t].fixed) {
        tf.theta = Eigen::VectorXd::Ones(k);
        tf.sigma = Eigen::VectorXd::Zero(k);
        tf.covariance = Eigen::MatrixXd::Zero(k, k);
      } else {
        const SlowNoise& sn = slowNoiseFor(t, withoutTerm(model, t));
        auto it = fits.find(&sn);
        if (it == fits.end()) it = fits.emplace(&sn, solve(sn.G, sn.b, sn.yy, S, F, true)).first;
        const ModelFit& fit = it->second;
        tf.theta = fit.theta.segment(pos, k);
        tf.inflation_factor = sn.term_inflation[t];
        tf.covariance = fit.A_inv.block(pos, pos, k, k) * (inflation_ * tf.inflation_factor);
        if (opt_.random_walk_sandwich && sn.has_law && !isSlow(t)) {
          auto cov = sandwich.find(&sn);
          if (cov == sandwich.end())
            cov = sandwich.emplace(&sn, fit.A_inv * randomWalkMeat(sn, fit.free_cols) * fit.A_inv)
                      .first;
          tf.covariance = atLeastTheVariances(
              tf.covariance, cov->second.block(pos, pos, k, k) * (inflation_ * tf.inflation_factor));
        }
        for (int i = 0; i < k; ++i)
          if (fit.unobservable[pos + i]) tf.covariance(i, i) = std::numeric_limits<double>::infinity();
        tf.sigma = tf.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
        pos += k;
      }
      if (terms_[t].nuisance) {
        res.nuisance = tf;
      } else {
        evidence(model, t, &tf.delta_bic, &tf.cv_gain);
        tf.claimed = terms_[t].part_of.empty() && passes(tf.delta_bic, tf.cv_gain);
        if (tf.claimed) {
          const auto [margin, alternative] = nameMargin(model, t);
          if (alternative >= 0) {
            tf.shape_alternative = alternative;
            tf.name_margin = margin;
            tf.name_ambiguous = margin < opt_.min_name_margin;
            tf.claimed = !tf.name_ambiguous;
          }
        }
        res.selected.push_back(tf);
      }
    }
    for (std::size_t t = 1; t < terms_.size(); ++t) {
      const int ti = static_cast<int>(t);
      if (std::find(model.begin(), model.end(), ti) != model.end() || terms_[t].fixed ||
          terms_[t].gauge_only)
        continue;
      res.limits.push_back({ti, detectionLimit(model, ti)});
    }
    // Parameters are whitened-scale free: the columns and residual were divided by the same
    // sigma_c, so theta is in SI units already.
    return res;
  }

  Eigen::MatrixXd residualOf(const Eigen::MatrixXd& r, const std::vector<int>& model,
                             const ModelFit& fit, int rb, int re) const {
    const int n = static_cast<int>(r.rows());
    Eigen::MatrixXd pred = Eigen::MatrixXd::Zero(n, kMismatchChannels);
    int pos = 0;
    for (int t : model) {
      const int k = map_.count[t];
      Eigen::VectorXd th = Eigen::VectorXd::Ones(k);
      if (!terms_[t].fixed) {
        th = fit.theta.segment(pos, k);
        pos += k;
      }
      pred += termContribution(terms_[t], th, n);
    }
    return (r - pred).middleRows(rb, re - rb);
  }

  const std::vector<CandidateTerm>& terms_;
  SelectionOptions opt_;
  ColumnMap map_;
  GramSet gram_;
  Eigen::Matrix<double, 6, 1> rho_ = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> sigma_ = Eigen::Matrix<double, 6, 1>::Ones();
  double inflation_ = 1.0;
  const Eigen::MatrixXd& r_;
  int rb_ = 0, re_ = 0;
  std::vector<int> full_;  // the largest model (noise model)
  std::vector<double> prior_variance_;  // per term, whitened units (priorVariances)
  // Per column: the unit-information prior of that column alone (priorVariances; step 5).
  std::vector<double> column_prior_variance_;
  mutable std::map<std::vector<int>, SlowNoise> slow_cache_;  // SlowNoise addresses are stable
  mutable std::map<std::pair<const SlowNoise*, std::vector<int>>, double> cv_cache_;
  mutable std::unique_ptr<std::array<ChannelLevels, kMismatchChannels>> level_grams_;
};

void checkInputs(const Eigen::MatrixXd& residual, const std::vector<CandidateTerm>& terms,
                 int row_begin, int* row_end) {
  if (residual.cols() != kMismatchChannels)
    throw std::invalid_argument("selectTerms: residual has " + std::to_string(residual.cols()) +
                                " columns, expected 6");
  if (terms.empty() || !terms[0].nuisance)
    throw std::invalid_argument("selectTerms: term 0 must be the nuisance constant bias");
  if (*row_end < 0) *row_end = static_cast<int>(residual.rows());
  if (row_begin < 0 || *row_end > residual.rows() || *row_end - row_begin < 20)
    throw std::invalid_argument("selectTerms: row range [" + std::to_string(row_begin) + ", " +
                                std::to_string(*row_end) + ") is invalid or shorter than 20 bins");
  for (const CandidateTerm& t : terms)
    for (const RegressorColumn& c : t.columns)
      for (int ch = 0; ch < kMismatchChannels; ++ch)
        if (c.actsOn(ch) && c.channel[ch].size() != residual.rows())
          throw std::invalid_argument("selectTerms: term " + t.key() +
                                      " has a regressor of the wrong length");
}

}  // namespace

SelectionResult selectTerms(const Eigen::MatrixXd& residual, const std::vector<CandidateTerm>& terms,
                            const SelectionOptions& options, int row_begin, int row_end) {
  options.validate();
  checkInputs(residual, terms, row_begin, &row_end);
  Selector sel(residual, terms, options, row_begin, row_end);
  std::vector<int> model = {0};
  std::vector<std::string> log;
  // Stepwise: forward selection, then backward elimination; after a drop the smaller model can
  // admit a term the dropped one had masked (e.g. a g-sensitivity whose lateral part a gyro
  // non-orthogonality absorbed before the misalignment came in), so forward runs again, until a
  // backward pass drops nothing or a model repeats.
  std::set<std::vector<int>> visited;
  int steps = 0;
  for (;;) {
    for (; steps < options.max_terms; ++steps) {
      int best = -1;
      double best_bic = 0.0, best_cv = 0.0;
      std::vector<int> best_trial;
      for (std::size_t t = 1; t < terms.size(); ++t) {
        if (terms[t].gauge_only || !terms[t].part_of.empty() ||
            std::find(model.begin(), model.end(), static_cast<int>(t)) != model.end())
          continue;
        const std::vector<int> base_model = sel.baseFor(model, static_cast<int>(t));
        const std::vector<int> trial = sel.withTerm(base_model, static_cast<int>(t));
        if (trial == base_model) continue;
        // A term whose required terms are hierarchy (paid_requires) is measured together with
        // them against the model; others (earth/gravity) against the model with them.
        const std::vector<int>& ref = terms[t].paid_requires ? model : base_model;
        const double dbic = sel.deltaBic(ref, trial, static_cast<int>(t));
        const double cvg = sel.cvGain(ref, trial, static_cast<int>(t));
        if (sel.passes(dbic, cvg) && (best < 0 || dbic > best_bic)) {
          best = static_cast<int>(t);
          best_bic = dbic;
          best_cv = cvg;
          best_trial = trial;
        }
      }
      if (best < 0) break;
      model = best_trial;
      log.push_back(fmt::format("add {} (delta_bic {:.1f}, cv_gain {:.4f})", terms[best].key(),
                                best_bic, best_cv));
    }
    // Backward elimination.
    bool dropped = false;
    for (;;) {
      int worst = -1;
      double worst_bic = 0.0;
      for (int t : model) {
        if (terms[t].nuisance || sel.requiredByOthers(model, t)) continue;
        double dbic = 0.0, cvg = 0.0;
        sel.evidence(model, t, &dbic, &cvg);
        if (!sel.passes(dbic, cvg) && (worst < 0 || dbic < worst_bic)) {
          worst = t;
          worst_bic = dbic;
        }
      }
      if (worst < 0) break;
      model = sel.withoutTerm(model, worst);
      dropped = true;
      log.push_back(fmt::format("drop {} (delta_bic {:.1f})", terms[worst].key(), worst_bic));
    }
    if (!dropped || !visited.insert(model).second) break;
  }
  model = sel.gaugeFixed(model, &log);
  SelectionResult res = sel.result(model);
  res.log = std::move(log);
  return res;
}

SelectionResult fitTerms(const Eigen::MatrixXd& residual, const std::vector<CandidateTerm>& terms,
                         const std::vector<int>& term_indices, const SelectionOptions& options,
                         int row_begin, int row_end) {
  options.validate();
  checkInputs(residual, terms, row_begin, &row_end);
  Selector sel(residual, terms, options, row_begin, row_end);
  std::vector<int> model = {0};
  for (int t : term_indices) {
    if (t <= 0 || t >= static_cast<int>(terms.size()))
      throw std::invalid_argument("fitTerms: term index " + std::to_string(t) + " out of range");
    model = sel.withRequired(model, t);
  }
  model = sel.withoutOrphanParts(model);
  return sel.result(model);
}

Eigen::MatrixXd predictSelection(const SelectionResult& sel, const std::vector<CandidateTerm>& terms,
                                 int n, bool include_nuisance) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  for (const TermFit& tf : sel.selected) out += termContribution(terms[tf.term], tf.theta, n);
  if (include_nuisance && sel.nuisance.term >= 0)
    out += termContribution(terms[sel.nuisance.term], sel.nuisance.theta, n);
  return out;
}

}  // namespace graftnav
