#include "graftnav/mismatch/term_selection.h"

#include <fmt/core.h>

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

#include "graftnav/mismatch/term_spec.h"
#include "selection_evidence.h"
#include "selection_gram.h"
#include "selection_models.h"
#include "selection_noise_model.h"
#include "slow_noise.h"

namespace graftnav {

void SelectionOptions::validate() const {
  if (folds < 2)
    throw std::invalid_argument("SelectionOptions: folds = " + std::to_string(folds) +
                                " must be >= 2");
  if (max_terms < 0) throw std::invalid_argument("SelectionOptions: max_terms must be >= 0");
  if (!(max_rho > 0.0 && max_rho < 1.0))
    throw std::invalid_argument("SelectionOptions: max_rho must be in (0, 1)");
  if (!(replay_period_s >= 0.0) || !(bin_s >= 0.0))
    throw std::invalid_argument("SelectionOptions: replay_period_s and bin_s must be >= 0");
  if (!(min_name_margin >= 0.0))
    throw std::invalid_argument("SelectionOptions: min_name_margin must be >= 0");
}

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

using selection_detail::modelColumns;
using selection_detail::ModelFit;
using selection_detail::SelectionEvidence;
using selection_detail::SelectionNoiseModel;
using selection_detail::SlowNoise;
using selection_detail::SlowNoiseEstimator;
using selection_detail::solve;
using selection_detail::TermModels;

// The selection over one residual and candidate library, in its parts: the model algebra, the
// noise model (AR(1), inflation, priors), the slow noise (GLS over Haar scales, block means) and
// the evidence, each built on the ones before.
class Selector {
 public:
  Selector(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
           const SelectionOptions& opt, int rb, int re)
      : terms_(terms),
        opt_(opt),
        models_(terms),
        noise_(r, terms, opt, rb, re, models_),
        slow_(noise_, models_),
        evidence_(noise_, slow_, models_) {}

  const TermModels& models() const { return models_; }
  const SelectionEvidence& evidence() const { return evidence_; }
  // Every term of `model` with its estimate, covariance and evidence; the detection limits of
  // every candidate left out.
  SelectionResult result(const std::vector<int>& model) const;

 private:
  const std::vector<CandidateTerm>& terms_;
  SelectionOptions opt_;
  TermModels models_;
  SelectionNoiseModel noise_;
  SlowNoiseEstimator slow_;
  SelectionEvidence evidence_;
};

SelectionResult Selector::result(const std::vector<int>& model) const {
  SelectionResult res;
  res.rho = noise_.rho();
  res.sigma = noise_.sigma();
  res.inflation = noise_.inflation();
  res.slow_inflation = slow_.slowNoise(model).slow_inflation;
  res.rows = noise_.gram().rows;
  std::vector<int> S, F;
  modelColumns(model, terms_, noise_.map(), &S, &F);
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
    const int k = noise_.map().count[t];
    if (terms_[t].fixed()) {
      tf.theta = Eigen::VectorXd::Ones(k);
      tf.sigma = Eigen::VectorXd::Zero(k);
      tf.covariance = Eigen::MatrixXd::Zero(k, k);
    } else {
      const SlowNoise& sn = slow_.slowNoiseFor(t, models_.withoutTerm(model, t));
      auto it = fits.find(&sn);
      if (it == fits.end()) it = fits.emplace(&sn, solve(sn.G, sn.b, sn.yy, S, F, true)).first;
      const ModelFit& fit = it->second;
      tf.theta = fit.theta.segment(pos, k);
      tf.inflation_factor = sn.term_inflation[t];
      tf.covariance = fit.A_inv.block(pos, pos, k, k) * (noise_.inflation() * tf.inflation_factor);
      if (opt_.random_walk_sandwich && sn.has_law && !models_.isSlow(t)) {
        auto cov = sandwich.find(&sn);
        if (cov == sandwich.end())
          cov =
              sandwich.emplace(&sn, fit.A_inv * slow_.randomWalkMeat(sn, fit.free_cols) * fit.A_inv)
                  .first;
        tf.covariance =
            atLeastTheVariances(tf.covariance, cov->second.block(pos, pos, k, k) *
                                                   (noise_.inflation() * tf.inflation_factor));
      }
      for (int i = 0; i < k; ++i)
        if (fit.unobservable[pos + i])
          tf.covariance(i, i) = std::numeric_limits<double>::infinity();
      tf.sigma = tf.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
      pos += k;
    }
    if (terms_[t].nuisance()) {
      res.nuisance = tf;
    } else {
      evidence_.termEvidence(model, t, &tf.delta_bic, &tf.cv_gain);
      tf.claimed = !terms_[t].part_of.has_value() && evidence_.passes(tf.delta_bic, tf.cv_gain);
      if (tf.claimed) {
        const auto [margin, alternative] = evidence_.nameMargin(model, t);
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
    if (std::find(model.begin(), model.end(), ti) != model.end() || terms_[t].fixed() ||
        terms_[t].gauge_only)
      continue;
    res.limits.push_back({ti, evidence_.detectionLimit(model, ti)});
  }
  // Parameters are whitened-scale free: the columns and residual were divided by the same
  // sigma_c, so theta is in SI units already.
  return res;
}

void checkInputs(const Eigen::MatrixXd& residual, const std::vector<CandidateTerm>& terms,
                 int row_begin, int* row_end) {
  if (residual.cols() != kMismatchChannels)
    throw std::invalid_argument("selectTerms: residual has " + std::to_string(residual.cols()) +
                                " columns, expected 6");
  if (terms.empty() || !terms[0].nuisance())
    throw std::invalid_argument("selectTerms: term 0 must be the nuisance constant bias");
  if (*row_end < 0) *row_end = static_cast<int>(residual.rows());
  if (row_begin < 0 || *row_end > residual.rows() || *row_end - row_begin < 20)
    throw std::invalid_argument("selectTerms: row range [" + std::to_string(row_begin) + ", " +
                                std::to_string(*row_end) + ") is invalid or shorter than 20 bins");
  for (const CandidateTerm& t : terms)
    for (const RegressorColumn& c : t.columns)
      for (int ch = 0; ch < kMismatchChannels; ++ch)
        if (c.actsOn(ch) &&
            (c.gridRows(ch) != residual.rows() || c.first_row < 0 || c.endRow(ch) > c.gridRows(ch)))
          throw std::invalid_argument("selectTerms: term " + t.key().text() +
                                      " has a regressor of the wrong length");
}

}  // namespace

SelectionResult selectTerms(const Eigen::MatrixXd& residual,
                            const std::vector<CandidateTerm>& terms,
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
        if (terms[t].gauge_only || terms[t].part_of.has_value() ||
            std::find(model.begin(), model.end(), static_cast<int>(t)) != model.end())
          continue;
        const std::vector<int> base_model = sel.models().baseFor(model, static_cast<int>(t));
        const std::vector<int> trial = sel.models().withTerm(base_model, static_cast<int>(t));
        if (trial == base_model) continue;
        // A term whose required terms are hierarchy (paid_requires) is measured together with
        // them against the model; others (earth/gravity) against the model with them.
        const std::vector<int>& ref = terms[t].spec->paid_requires ? model : base_model;
        const double dbic = sel.evidence().deltaBic(ref, trial, static_cast<int>(t));
        const double cvg = sel.evidence().cvGain(ref, trial, static_cast<int>(t));
        if (sel.evidence().passes(dbic, cvg) && (best < 0 || dbic > best_bic)) {
          best = static_cast<int>(t);
          best_bic = dbic;
          best_cv = cvg;
          best_trial = trial;
        }
      }
      if (best < 0) break;
      model = best_trial;
      log.push_back(fmt::format("add {} (delta_bic {:.1f}, cv_gain {:.4f})",
                                terms[best].key().text(), best_bic, best_cv));
    }
    // Backward elimination.
    bool dropped = false;
    for (;;) {
      int worst = -1;
      double worst_bic = 0.0;
      for (int t : model) {
        if (terms[t].nuisance() || sel.models().requiredByOthers(model, t)) continue;
        double dbic = 0.0, cvg = 0.0;
        sel.evidence().termEvidence(model, t, &dbic, &cvg);
        if (!sel.evidence().passes(dbic, cvg) && (worst < 0 || dbic < worst_bic)) {
          worst = t;
          worst_bic = dbic;
        }
      }
      if (worst < 0) break;
      model = sel.models().withoutTerm(model, worst);
      dropped = true;
      log.push_back(
          fmt::format("drop {} (delta_bic {:.1f})", terms[worst].key().text(), worst_bic));
    }
    if (!dropped || !visited.insert(model).second) break;
  }
  model = sel.models().gaugeFixed(model, &log);
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
    model = sel.models().withRequired(model, t);
  }
  model = sel.models().withoutOrphanParts(model);
  return sel.result(model);
}

Eigen::MatrixXd predictSelection(const SelectionResult& sel,
                                 const std::vector<CandidateTerm>& terms, int n,
                                 bool include_nuisance) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  for (const TermFit& tf : sel.selected) out += termContribution(terms[tf.term], tf.theta, n);
  if (include_nuisance && sel.nuisance.term >= 0)
    out += termContribution(terms[sel.nuisance.term], sel.nuisance.theta, n);
  return out;
}

}  // namespace graftnav