#include "selection_evidence.h"

#include "graftnav/mismatch/term_spec.h"

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

SelectionEvidence::SelectionEvidence(const SelectionNoiseModel& noise,
                                     const SlowNoiseEstimator& slow, const TermModels& models)
    : terms_(noise.terms()), opt_(noise.options()), noise_(noise), slow_(slow), models_(models) {}

// Evidence of going from `without` to `with` for term t: twice the log Bayes factor of the
// two models (header, step 2). With a term that replaces another (excludes) the models are not
// nested; both are then measured against the terms they share.
// `column_prior`: the added columns under their own priors (step 5's names).
double SelectionEvidence::deltaBic(const std::vector<int>& without, const std::vector<int>& with,
                                   int t, bool column_prior) const {
  const SlowNoise& sn = slow_.slowNoiseFor(t, without);
  std::vector<int> common;
  std::set_intersection(without.begin(), without.end(), with.begin(), with.end(),
                        std::back_inserter(common));
  const double c = noise_.inflation() * sn.term_inflation[t];
  double e = evidenceOver(common, with, sn, c, column_prior);
  if (common != without) e -= evidenceOver(common, without, sn, c, column_prior);
  return e;
}

// `column_prior`: each added column under its own unit-information prior (step 5) instead of
// its term's isotropic one.
AddedInformation SelectionEvidence::addedInformation(const std::vector<int>& base,
                                                     const std::vector<int>& model,
                                                     const SlowNoise& sn, bool column_prior) const {
  AddedInformation ai;
  std::vector<int> added;
  std::set_difference(model.begin(), model.end(), base.begin(), base.end(),
                      std::back_inserter(added));
  modelColumns(base, terms_, noise_.map(), &ai.Sb, &ai.Fb);
  modelColumns(added, terms_, noise_.map(), &ai.Sa, &ai.Fa);
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
    if (terms_[t].fixed()) continue;
    for (int j = 0; j < noise_.map().count[t]; ++j) {
      const int col = noise_.map().start[t] + j;
      const int i = static_cast<int>(std::find(ai.Sa.begin(), ai.Sa.end(), col) - ai.Sa.begin());
      ai.sd(i) =
          std::sqrt(column_prior ? noise_.columnPriorVariances()[col] : noise_.priorVariances()[t]);
    }
  }
  return ai;
}

// Eigen-decomposition of the prior-scaled information sd A sd, eigenvalues floored.
Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> SelectionEvidence::scaledInformation(
    const AddedInformation& ai, Eigen::VectorXd* s) {
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
double SelectionEvidence::evidenceOver(const std::vector<int>& base, const std::vector<int>& model,
                                       const SlowNoise& sn, double c, bool column_prior) const {
  const AddedInformation ai = addedInformation(base, model, sn, column_prior);
  double gain = 0.0;
  if (!ai.Fa.empty())
    gain += (solve(sn.G, sn.b, sn.yy, ai.Sb, ai.Fb, false).rss -
             solve(sn.G, sn.b, sn.yy, ai.Sb, ai.F, false).rss) /
            c;
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
Eigen::VectorXd SelectionEvidence::detectionLimit(const std::vector<int>& model, int t) const {
  const int k = noise_.map().count[t];
  Eigen::VectorXd limit = Eigen::VectorXd::Constant(k, std::numeric_limits<double>::infinity());
  const std::vector<int> base = models_.baseFor(model, t);
  const std::vector<int> with = models_.withTerm(base, t);
  if (with == base || terms_[t].fixed() || terms_[t].nuisance()) return limit;
  std::vector<int> common;
  std::set_intersection(base.begin(), base.end(), with.begin(), with.end(),
                        std::back_inserter(common));
  const SlowNoise& sn = slow_.slowNoiseFor(t, base);
  const AddedInformation ai = addedInformation(common, with, sn);
  if (ai.Sa.empty()) return limit;
  const double c = noise_.inflation() * sn.term_inflation[t];
  Eigen::VectorXd s;
  const auto eig = scaledInformation(ai, &s);
  double P = 0.0;
  for (int i = 0; i < s.size(); ++i) P += std::log1p(s(i));
  for (int j = 0; j < k; ++j) {
    const int col = noise_.map().start[t] + j;
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

// Blocked CV error of `model` in the metric of the noise `sn` (the slow noise the term under
// test is measured against: GLS per fold for a fast term, white for a slow one).
double SelectionEvidence::cvError(const std::vector<int>& model, const SlowNoise& sn) const {
  const auto key = std::make_pair(&sn, model);
  const auto it = cv_cache_.find(key);
  if (it != cv_cache_.end()) return it->second;
  std::vector<int> S, F;
  modelColumns(model, terms_, noise_.map(), &S, &F);
  Eigen::MatrixXd G_sum = Eigen::MatrixXd::Zero(noise_.map().total, noise_.map().total);
  Eigen::VectorXd b_sum = Eigen::VectorXd::Zero(noise_.map().total);
  double yy_sum = 0.0;
  for (int f = 0; f < opt_.folds; ++f) {
    G_sum += sn.G_fold[f];
    b_sum += sn.b_fold[f];
    yy_sum += sn.yy_fold[f];
  }
  double cv = 0.0;
  for (int f = 0; f < opt_.folds; ++f) {
    const ModelFit tr =
        solve(G_sum - sn.G_fold[f], b_sum - sn.b_fold[f], yy_sum - sn.yy_fold[f], S, F, false);
    cv += foldError(tr, sn.G_fold[f], sn.b_fold[f], sn.yy_fold[f]);
  }
  cv_cache_.emplace(key, cv);
  return cv;
}

// Relative CV improvement of `with` over `without` for term t, in t's noise metric.
double SelectionEvidence::cvGain(const std::vector<int>& without, const std::vector<int>& with,
                                 int t) const {
  const SlowNoise& sn = slow_.slowNoiseFor(t, without);
  const double ref = cvError(without, sn);
  return ref > 0.0 ? (ref - cvError(with, sn)) / ref : 0.0;
}

void SelectionEvidence::termEvidence(const std::vector<int>& model, int t, double* delta_bic,
                                     double* cv_gain) const {
  const std::vector<int> base = models_.withoutTerm(model, t);
  *delta_bic = deltaBic(base, model, t);
  *cv_gain = cvGain(base, model, t);
}

bool SelectionEvidence::passes(double delta_bic, double cv_gain) const {
  return delta_bic > opt_.min_delta_bic && cv_gain > opt_.min_cv_gain;
}

// Step 5: the evidence of term t (in `model`) over its best shape alternative, the model with
// that alternative (and what it requires) in t's place, each added column under the
// unit-information prior of that column alone; and the alternative's index (-1: none applies,
// e.g. both shapes are in the model and each was measured against the other).
std::pair<double, int> SelectionEvidence::nameMargin(const std::vector<int>& model, int t) const {
  std::pair<double, int> best{std::numeric_limits<double>::infinity(), -1};
  const std::vector<TermKind>& kinds = terms_[t].spec->shape_alternatives;
  if (kinds.empty()) return best;
  const std::vector<int> without = models_.withoutTerm(model, t);
  for (std::size_t u = 1; u < terms_.size(); ++u) {
    const CandidateTerm& cu = terms_[u];
    const int ui = static_cast<int>(u);
    if (cu.sensor != terms_[t].sensor || cu.nuisance() || cu.fixed() || cu.gauge_only ||
        cu.part_of.has_value() || std::find(kinds.begin(), kinds.end(), cu.kind()) == kinds.end() ||
        std::find(model.begin(), model.end(), ui) != model.end())
      continue;
    const std::vector<int> alternative = models_.withRequired(without, ui);
    if (alternative == without) continue;
    const double margin = deltaBic(alternative, model, t, /*column_prior=*/true);
    if (margin < best.first) best = {margin, ui};
  }
  return best;
}

}  // namespace graftnav::selection_detail
