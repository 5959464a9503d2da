#pragma once
// Internal to the mismatch module's term selection (term_selection.h), step 1 of the selection:
// the noise model. The largest model (all candidates) gives per channel an AR(1) coefficient rho
// and innovation sigma; residual and regressors are prewhitened with them (the Gram matrices of
// every later fit), and what AR(1) leaves (lag-1 correlation of the whitened residual) and any
// excess variance become an inflation c >= 1. Also the unit-information priors of the evidence.
#include <Eigen/Core>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/term_selection.h"
#include "selection_gram.h"
#include "selection_models.h"

namespace graftnav::selection_detail {

class SelectionNoiseModel {
 public:
  // `r` (n x 6) and `terms` must outlive the model; rows [rb, re) are fitted.
  SelectionNoiseModel(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                      const SelectionOptions& opt, int rb, int re, const TermModels& models);

  const std::vector<CandidateTerm>& terms() const { return terms_; }
  const SelectionOptions& options() const { return opt_; }
  const ColumnMap& map() const { return map_; }
  const GramSet& gram() const { return gram_; }  // AR(1)-whitened, per fold
  const Eigen::Matrix<double, 6, 1>& rho() const { return rho_; }
  const Eigen::Matrix<double, 6, 1>& sigma() const { return sigma_; }
  double inflation() const { return inflation_; }  // c
  const Eigen::MatrixXd& residual() const { return r_; }
  int rowBegin() const { return rb_; }
  int rowEnd() const { return re_; }
  const std::vector<int>& fullModel() const { return full_; }
  // Per term, the prior variance of step 2 (whitened units); per column, that column's alone.
  const std::vector<double>& priorVariances() const { return prior_variance_; }
  const std::vector<double>& columnPriorVariances() const { return column_prior_variance_; }

  // Whitened series (AR(1) of channel c, divided by its innovation scale) over the selection
  // rows starting at `offset`, mean removed (the nuisance constant), as the fit sees it.
  Eigen::VectorXd whitened(const Eigen::VectorXd& z, int c, int offset) const;

 private:
  void computePriorVariances();

  const std::vector<CandidateTerm>& terms_;
  SelectionOptions opt_;
  ColumnMap map_;
  GramSet gram_;
  Eigen::Matrix<double, 6, 1> rho_ = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> sigma_ = Eigen::Matrix<double, 6, 1>::Ones();
  double inflation_ = 1.0;
  const Eigen::MatrixXd& r_;
  int rb_ = 0, re_ = 0;
  std::vector<int> full_;                      // the largest model
  std::vector<double> prior_variance_;         // per term (computePriorVariances)
  std::vector<double> column_prior_variance_;  // per column (step 5's names)
};

}  // namespace graftnav::selection_detail
