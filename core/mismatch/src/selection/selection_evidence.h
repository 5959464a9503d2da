#pragma once
// Internal to the mismatch module's term selection (term_selection.h), step 2: the evidence of a
// term (2 ln of the Laplace Bayes factor under a unit-information prior), its blocked
// cross-validation gain in the metric of its noise, the detection limit of a term left out, and
// the margin of a name over its shape alternative.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <map>
#include <utility>
#include <vector>

#include "selection_models.h"
#include "selection_noise_model.h"
#include "slow_noise.h"

namespace graftnav::selection_detail {

// Information of the columns a model adds to a base model, the base projected out: what the
// Laplace evidence and the detection limit are computed from.
struct AddedInformation {
  std::vector<int> Sb, Fb, Sa, Fa, F;  // free / fixed columns of the base and of the added terms
  Eigen::MatrixXd A;                   // information of the added free columns, base projected out
  Eigen::VectorXd r;                   // their score (whitened X'y net of the fixed columns)
  Eigen::VectorXd sd;                  // prior standard deviation per added free column
};

class SelectionEvidence {
 public:
  // `noise`, `slow` and `models` must outlive the evidence.
  SelectionEvidence(const SelectionNoiseModel& noise, const SlowNoiseEstimator& slow,
                    const TermModels& models);

  // Evidence of going from `without` to `with` for term t (`column_prior`: the added columns
  // under their own priors, as the names of step 5 are measured).
  double deltaBic(const std::vector<int>& without, const std::vector<int>& with, int t,
                  bool column_prior = false) const;
  // Relative CV improvement of `with` over `without` for term t, in t's noise metric.
  double cvGain(const std::vector<int>& without, const std::vector<int>& with, int t) const;
  // delta_bic and cv_gain of term t in `model` against `model` without it.
  void termEvidence(const std::vector<int>& model, int t, double* delta_bic, double* cv_gain) const;
  bool passes(double delta_bic, double cv_gain) const;
  // Per column of term t (not in `model`), the value whose noise-free evidence reaches the claim
  // threshold; infinite for a column without information.
  Eigen::VectorXd detectionLimit(const std::vector<int>& model, int t) const;
  // The evidence of t over its best shape alternative in its place, and that alternative's index
  // (-1: none applies).
  std::pair<double, int> nameMargin(const std::vector<int>& model, int t) const;

 private:
  AddedInformation addedInformation(const std::vector<int>& base, const std::vector<int>& model,
                                    const SlowNoise& sn, bool column_prior = false) const;
  static Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> scaledInformation(
      const AddedInformation& ai, Eigen::VectorXd* s);
  double evidenceOver(const std::vector<int>& base, const std::vector<int>& model,
                      const SlowNoise& sn, double c, bool column_prior = false) const;
  double cvError(const std::vector<int>& model, const SlowNoise& sn) const;

  const std::vector<CandidateTerm>& terms_;
  const SelectionOptions& opt_;
  const SelectionNoiseModel& noise_;
  const SlowNoiseEstimator& slow_;
  const TermModels& models_;
  mutable std::map<std::pair<const SlowNoise*, std::vector<int>>, double> cv_cache_;
};

}  // namespace graftnav::selection_detail
