#pragma once
// Internal to the mismatch module's term selection (term_selection.h): the AR(1)-whitened normal
// equations of the candidate columns, accumulated once per cross-validation fold, and least
// squares on them, so that every trial fit is a small dense solve whatever the record length.
// The normal equations are summed block by block of rows: only one block of whitened columns
// is made at a time, and only of the columns non-zero there (a bias_instability hat touches a
// few blocks).
#include <Eigen/Core>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"

namespace graftnav::selection_detail {

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

// Where each term's columns sit among all candidate columns.
struct ColumnMap {
  std::vector<int> start, count;
  int total = 0;
};

ColumnMap mapColumns(const std::vector<CandidateTerm>& terms);

// Row i (from rb) of z prewhitened by AR(1) rho and scaled by w; the first row keeps the
// stationary variance (sqrt(1 - rho^2)).
double whitenedRow(const Eigen::VectorXd& z, int rb, int i, double rho, double w);
// The same for channel c of a regressor column (zero outside its stored stretch).
double whitenedRow(const RegressorColumn& u, int c, int rb, int i, double rho, double w);

// The candidate columns acting on channel c: their global indices and their columns.
struct ChannelColumns {
  int channel = 0;
  std::vector<int> idx;
  std::vector<const RegressorColumn*> src;
};
ChannelColumns channelColumns(const std::vector<CandidateTerm>& terms, const ColumnMap& map, int c);

// The columns `cols` on their channel, and `last` as one more column when given, whitened over
// `len` rows from row rb (whitenedRow): the rows the fit sees.
Eigen::MatrixXd whitenedColumns(const ChannelColumns& cols, const Eigen::VectorXd* last, int rb,
                                int len, double rho, double w);
// Rows [a, b) (counted from rb) of whitenedColumns.
Eigen::MatrixXd whitenedBlock(const ChannelColumns& cols, const Eigen::VectorXd* last, int rb,
                              int a, int b, double rho, double w);

// First row of CV fold f of `folds` contiguous folds over `len` rows.
int foldStart(int len, int f, int folds);

// Rows per block of the normal equations' accumulation (~3.4 min of 0.05-s bins; a block of 40
// whitened columns is 1.3 MB).
inline constexpr int kGramBlockRows = 4096;

// The whitened normal equations of all candidate columns and the residual r over rows [rb, re),
// per fold and summed, accumulated over blocks of `block_rows` rows (a block never spans two
// folds). Equal to the products of the whole whitened columns up to the order of summation.
GramSet accumulate(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                   const ColumnMap& map, const Eigen::Matrix<double, 6, 1>& rho,
                   const Eigen::Matrix<double, 6, 1>& weight, int rb, int re, int folds,
                   int block_rows = kGramBlockRows);

struct ModelFit {
  std::vector<int> free_cols, fixed_cols;
  Eigen::VectorXd theta;
  Eigen::MatrixXd A_inv;
  std::vector<bool> unobservable;  // free columns with no signal (e.g. max(x, 0) of a negative x)
  double rss = 0.0;
};

// Free and fixed columns of a set of terms.
void modelColumns(const std::vector<int>& model, const std::vector<CandidateTerm>& terms,
                  const ColumnMap& map, std::vector<int>* free_cols, std::vector<int>* fixed_cols);

// A normal matrix made safely invertible: a relative ridge of 1e-11, and all-zero columns (no
// signal: theta 0, sigma infinite) pinned; `pinned`, when given, marks them.
Eigen::MatrixXd regularized(const Eigen::MatrixXd& A, std::vector<bool>* pinned = nullptr);

// Least squares on G, b, yy over the free columns S with the fixed columns' coefficients at 1.
ModelFit solve(const Eigen::MatrixXd& G, const Eigen::VectorXd& b, double yy,
               const std::vector<int>& S, const std::vector<int>& F, bool want_inverse);

// Whitened squared prediction error of a fit on one fold's Gram.
double foldError(const ModelFit& fit, const Eigen::MatrixXd& G, const Eigen::VectorXd& b,
                 double yy);

// Rows [rb, re) of r minus the contributions of `model` with the coefficients of `fit`.
Eigen::MatrixXd residualOf(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                           const ColumnMap& map, const std::vector<int>& model, const ModelFit& fit,
                           int rb, int re);

}  // namespace graftnav::selection_detail
