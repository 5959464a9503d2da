#include "selection_gram.h"

#include <Eigen/Cholesky>
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

double whitenedRow(const RegressorColumn& u, int c, int rb, int i, double rho, double w) {
  const int t = rb + i;
  return i == 0 ? w * std::sqrt(std::max(0.0, 1.0 - rho * rho)) * u.at(c, t)
                : w * (u.at(c, t) - rho * u.at(c, t - 1));
}

// The candidate columns acting on channel c: their global indices and their columns.
ChannelColumns channelColumns(const std::vector<CandidateTerm>& terms, const ColumnMap& map,
                              int c) {
  ChannelColumns out;
  out.channel = c;
  for (std::size_t t = 0; t < terms.size(); ++t)
    for (int j = 0; j < map.count[t]; ++j)
      if (terms[t].columns[j].actsOn(c)) {
        out.idx.push_back(map.start[t] + j);
        out.src.push_back(&terms[t].columns[j]);
      }
  return out;
}

// The columns `cols`, and `last` as one more column when given, whitened over `len` rows from
// row rb (whitenedRow): the rows the fit sees.
Eigen::MatrixXd whitenedColumns(const ChannelColumns& cols, const Eigen::VectorXd* last, int rb,
                                int len, double rho, double w) {
  return whitenedBlock(cols, last, rb, 0, len, rho, w);
}

Eigen::MatrixXd whitenedBlock(const ChannelColumns& cols, const Eigen::VectorXd* last, int rb,
                              int a, int b, double rho, double w) {
  const int m = static_cast<int>(cols.src.size());
  Eigen::MatrixXd X(b - a, m + (last ? 1 : 0));
  for (int i = a; i < b; ++i) {
    for (int k = 0; k < m; ++k)
      X(i - a, k) = whitenedRow(*cols.src[k], cols.channel, rb, i, rho, w);
    if (last) X(i - a, m) = whitenedRow(*last, rb, i, rho, w);
  }
  return X;
}

// First row of CV fold f of `folds` contiguous folds over `len` rows (fold f is
// [foldStart(f), foldStart(f + 1))): the one partition the white and the GLS fold grams share.
int foldStart(int len, int f, int folds) {
  return static_cast<int>(static_cast<long>(len) * f / folds);
}

namespace {

// Adds rows [a, b) (counted from rb) of channel cols.channel to fold f: the whitened columns
// non-zero on those rows or on the row before (the AR(1) whitening reads it), and the residual.
void addBlock(const ChannelColumns& cols, const Eigen::MatrixXd& r, int rb, int a, int b,
              double rho, double w, int f, GramSet* g) {
  const int c = cols.channel;
  const int t0 = rb + std::max(0, a - 1), t1 = rb + b;
  std::vector<int> live;
  for (std::size_t k = 0; k < cols.src.size(); ++k)
    if (cols.src[k]->first_row < t1 && cols.src[k]->endRow(c) > t0)
      live.push_back(static_cast<int>(k));
  const int m = static_cast<int>(live.size()), len = b - a;
  Eigen::MatrixXd X(len, m);
  Eigen::VectorXd y(len);
  for (int i = 0; i < len; ++i) {
    for (int k = 0; k < m; ++k) X(i, k) = whitenedRow(*cols.src[live[k]], c, rb, a + i, rho, w);
    y(i) = w * (i + a == 0 ? std::sqrt(std::max(0.0, 1.0 - rho * rho)) * r(rb, c)
                           : r(rb + a + i, c) - rho * r(rb + a + i - 1, c));
  }
  const Eigen::MatrixXd Gb = X.transpose() * X;
  const Eigen::VectorXd bb = X.transpose() * y;
  for (int j = 0; j < m; ++j) {
    const int gj = cols.idx[live[j]];
    g->b[f](gj) += bb(j);
    for (int k = 0; k < m; ++k) g->G[f](gj, cols.idx[live[k]]) += Gb(j, k);
  }
  g->yy[f] += y.squaredNorm();
}

}  // namespace

GramSet accumulate(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                   const ColumnMap& map, const Eigen::Matrix<double, 6, 1>& rho,
                   const Eigen::Matrix<double, 6, 1>& weight, int rb, int re, int folds,
                   int block_rows) {
  if (block_rows < 1) throw std::invalid_argument("accumulate: block_rows must be >= 1");
  GramSet g;
  const int P = map.total;
  g.G.assign(folds, Eigen::MatrixXd::Zero(P, P));
  g.b.assign(folds, Eigen::VectorXd::Zero(P));
  g.yy.assign(folds, 0.0);
  const int len = re - rb;
  for (int c = 0; c < kMismatchChannels; ++c) {
    const ChannelColumns cols = channelColumns(terms, map, c);
    for (int f = 0; f < folds; ++f) {
      const int fold_end = foldStart(len, f + 1, folds);
      for (int a = foldStart(len, f, folds); a < fold_end; a += block_rows)
        addBlock(cols, r, rb, a, std::min(fold_end, a + block_rows), rho(c), weight(c), f, &g);
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

// Columns of a set of terms.
void modelColumns(const std::vector<int>& model, const std::vector<CandidateTerm>& terms,
                  const ColumnMap& map, std::vector<int>* free_cols, std::vector<int>* fixed_cols) {
  free_cols->clear();
  fixed_cols->clear();
  for (int t : model)
    for (int j = 0; j < map.count[t]; ++j)
      (terms[t].fixed() ? fixed_cols : free_cols)->push_back(map.start[t] + j);
}

// A normal matrix made safely invertible: a relative ridge of 1e-11, and all-zero columns (no
// signal: theta 0, sigma infinite) pinned; `pinned`, when given, marks them.
Eigen::MatrixXd regularized(const Eigen::MatrixXd& A, std::vector<bool>* pinned) {
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
double foldError(const ModelFit& fit, const Eigen::MatrixXd& G, const Eigen::VectorXd& b,
                 double yy) {
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

Eigen::MatrixXd residualOf(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                           const ColumnMap& map, const std::vector<int>& model, const ModelFit& fit,
                           int rb, int re) {
  const int n = static_cast<int>(r.rows());
  Eigen::MatrixXd pred = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  int pos = 0;
  for (int t : model) {
    const int k = map.count[t];
    Eigen::VectorXd th = Eigen::VectorXd::Ones(k);
    if (!terms[t].fixed()) {
      th = fit.theta.segment(pos, k);
      pos += k;
    }
    pred += termContribution(terms[t], th, n);
  }
  return (r - pred).middleRows(rb, re - rb);
}

}  // namespace graftnav::selection_detail
