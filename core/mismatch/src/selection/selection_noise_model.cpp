#include "selection_noise_model.h"

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

namespace graftnav::selection_detail {

SelectionNoiseModel::SelectionNoiseModel(const Eigen::MatrixXd& r,
                                         const std::vector<CandidateTerm>& terms,
                                         const SelectionOptions& opt, int rb, int re,
                                         const TermModels& models)
    : terms_(terms), opt_(opt), map_(mapColumns(terms)), r_(r), rb_(rb), re_(re) {
  // Noise model from the largest model: all candidates, one of each exclusive group.
  std::vector<int> full = {0};
  for (std::size_t t = 1; t < terms.size(); ++t) {
    if (terms[t].fixed() || terms[t].gauge_only) continue;
    full = models.withRequired(full, static_cast<int>(t));
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
    const Eigen::MatrixXd e = residualOf(r, terms_, map_, full, f0, rb, re);
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
    const Eigen::MatrixXd e = residualOf(r, terms_, map_, full, f1, rb, re);
    double num = 0.0, den = 0.0;
    for (int c = 0; c < kMismatchChannels; ++c) {
      Eigen::VectorXd ew(e.rows() - 1);
      for (Eigen::Index i = 1; i < e.rows(); ++i)
        ew(i - 1) = (e(i, c) - rho_(c) * e(i - 1, c)) / sigma_(c);
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
  computePriorVariances();
}

// The prior of step 2: isotropic within a term (its parameters share units), with the variance
// that makes the information of the term's average column, net of the nuisance, worth N / c
// observations ("unit information"): prior variance = (N / c) p / trace(D), D the whitened
// normal matrix of the term's columns with the nuisance projected out, p its columns with
// signal. A term whose columns are equally informative and orthogonal to the base gets
// s_i = N / c on every direction, the BIC penalty ln(1 + N / c) per parameter.
void SelectionNoiseModel::computePriorVariances() {
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
    if (terms_[t].fixed()) continue;
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

// Whitened series (AR(1) of channel c, divided by its innovation scale) over the selection
// rows, mean removed (the nuisance constant), as the fit sees it.
Eigen::VectorXd SelectionNoiseModel::whitened(const Eigen::VectorXd& z, int c, int offset) const {
  const int len = re_ - rb_;
  Eigen::VectorXd w(len);
  for (int i = 0; i < len; ++i) {
    const double prev = i > 0 ? z(offset + i - 1) : 0.0;
    w(i) = (z(offset + i) - (i > 0 ? rho_(c) * prev : 0.0)) / sigma_(c);
  }
  w.array() -= w.mean();
  return w;
}

}  // namespace graftnav::selection_detail
