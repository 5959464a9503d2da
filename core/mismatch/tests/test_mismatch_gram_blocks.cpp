// The selection's whitened normal equations summed block by block of rows, with the
// bias_instability columns held as the stretch where they are non-zero, against the products of
// the whole whitened columns held at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../src/selection/selection_gram.h"
#include "mismatch_signal_fixture.h"

namespace graftnav {
namespace {

using mismatch_test::ar1Noise;
using mismatch_test::carMotion;
using mismatch_test::syntheticInputs;
using selection_detail::accumulate;
using selection_detail::ColumnMap;
using selection_detail::foldStart;
using selection_detail::GramSet;
using selection_detail::mapColumns;

// The normal equations as products of the whole whitened columns, each column over every bin.
GramSet heldGram(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                 const ColumnMap& map, const Vector6d& rho, const Vector6d& w, int rb, int re,
                 int folds) {
  GramSet g;
  const int P = map.total, len = re - rb;
  g.G.assign(folds, Eigen::MatrixXd::Zero(P, P));
  g.b.assign(folds, Eigen::VectorXd::Zero(P));
  g.yy.assign(folds, 0.0);
  const auto whiten = [&](const Eigen::VectorXd& z, int c, int i) {
    const int t = rb + i;
    return i == 0 ? w(c) * std::sqrt(1.0 - rho(c) * rho(c)) * z(t)
                  : w(c) * (z(t) - rho(c) * z(t - 1));
  };
  for (int c = 0; c < kMismatchChannels; ++c) {
    std::vector<int> idx;
    std::vector<Eigen::VectorXd> cols;
    for (std::size_t t = 0; t < terms.size(); ++t)
      for (int j = 0; j < map.count[t]; ++j)
        if (terms[t].columns[j].actsOn(c)) {
          idx.push_back(map.start[t] + j);
          cols.push_back(terms[t].columns[j].dense(c));
        }
    const int m = static_cast<int>(idx.size());
    const Eigen::VectorXd rc = r.col(c);
    Eigen::MatrixXd X(len, m);
    Eigen::VectorXd y(len);
    for (int i = 0; i < len; ++i) {
      for (int k = 0; k < m; ++k) X(i, k) = whiten(cols[k], c, i);
      y(i) = whiten(rc, c, i);
    }
    for (int f = 0; f < folds; ++f) {
      const int a = foldStart(len, f, folds), b = foldStart(len, f + 1, folds);
      const Eigen::MatrixXd Gf = X.middleRows(a, b - a).transpose() * X.middleRows(a, b - a);
      const Eigen::VectorXd bf = X.middleRows(a, b - a).transpose() * y.segment(a, b - a);
      for (int j = 0; j < m; ++j) {
        g.b[f](idx[j]) += bf(j);
        for (int k = 0; k < m; ++k) g.G[f](idx[j], idx[k]) += Gf(j, k);
      }
      g.yy[f] += y.segment(a, b - a).squaredNorm();
    }
  }
  return g;
}

// Largest difference of two normal equations, each entry relative to its Cauchy-Schwarz bound
// sqrt(G_ii G_jj) (b: sqrt(G_ii yy)).
double relativeDifference(const Eigen::MatrixXd& G1, const Eigen::VectorXd& b1, double yy1,
                          const Eigen::MatrixXd& G2, const Eigen::VectorXd& b2, double yy2) {
  double worst = std::abs(yy1 - yy2) / yy2;
  for (Eigen::Index i = 0; i < G2.rows(); ++i) {
    const double bound_b = std::sqrt(G2(i, i) * yy2);
    if (bound_b > 0.0) worst = std::max(worst, std::abs(b1(i) - b2(i)) / bound_b);
    for (Eigen::Index j = 0; j < G2.cols(); ++j) {
      const double bound = std::sqrt(G2(i, i) * G2(j, j));
      if (bound > 0.0)
        worst = std::max(worst, std::abs(G1(i, j) - G2(i, j)) / bound);
      else
        EXPECT_EQ(G1(i, j), 0.0);
    }
  }
  return worst;
}

TEST(MismatchGramBlocks, BiasInstabilityColumnsHoldOnlyTheirKnotIntervals) {
  const RegressorInputs in = syntheticInputs(carMotion(11), 900.0, 0.0);
  const int n = in.reference.grid.count;
  CandidateLibraryOptions lo;
  lo.knot_spacing_s = 60.0;
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in, lo);
  const auto it = std::find_if(terms.begin(), terms.end(), [](const CandidateTerm& t) {
    return t.kind() == TermKind::bias_instability;
  });
  ASSERT_NE(it, terms.end());
  const double spacing = it->knot_spacing_s, bin_s = in.reference.grid.bin_s;
  ASSERT_GT(it->columns.size(), 6u);
  for (std::size_t j = 0; j < it->columns.size(); ++j) {
    const RegressorColumn& col = it->columns[j];
    const int k = static_cast<int>(j % (it->columns.size() / 3)) + 1;  // knot of this hat
    for (int c = 0; c < kMismatchChannels; ++c) {
      if (!col.actsOn(c)) continue;
      EXPECT_EQ(col.gridRows(c), n);
      EXPECT_LE(col.channel[c].size(), 2 * spacing / bin_s + 4);  // two knot intervals
      const Eigen::VectorXd v = col.dense(c);
      for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) * bin_s / spacing - k;
        ASSERT_EQ(v(i), std::max(0.0, 1.0 - std::abs(u))) << "knot " << k << " bin " << i;
      }
    }
  }
}

// Blocks of 97 rows: most block boundaries fall inside a knot interval (1200 bins), and some
// inside a hat's support, where the whitening of a block's first row reads the row before it.
TEST(MismatchGramBlocks, BlockedNormalEquationsEqualTheHeldOnes) {
  const RegressorInputs in = syntheticInputs(carMotion(5), 900.0, 0.0);
  const int n = in.reference.grid.count;
  CandidateLibraryOptions lo;
  lo.knot_spacing_s = 60.0;
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(in, lo);
  const ColumnMap map = mapColumns(terms);
  Eigen::MatrixXd r = ar1Noise(n, 0.6, 21);
  Eigen::VectorXd theta = Eigen::VectorXd::Constant(terms[3].columns.size(), 1e-3);
  r += termContribution(terms[3], theta, n);
  Vector6d rho, w;
  rho << 0.6, 0.5, 0.4, 0.3, 0.2, 0.1;
  w << 500.0, 400.0, 300.0, 50.0, 40.0, 30.0;
  const int rb = 17, re = n - 5, folds = 5, block = 97;
  // A block starts inside a hat's support: the hat is non-zero on its first row and the one
  // before.
  bool boundary_inside_hat = false;
  for (const CandidateTerm& t : terms)
    if (t.kind() == TermKind::bias_instability)
      for (int a = block; a < re - rb; a += block)
        boundary_inside_hat |=
            t.columns[0].at(0, rb + a) > 0.0 && t.columns[0].at(0, rb + a - 1) > 0.0;
  ASSERT_TRUE(boundary_inside_hat);

  const GramSet held = heldGram(r, terms, map, rho, w, rb, re, folds);
  for (const int rows : {block, 1, selection_detail::kGramBlockRows}) {
    const GramSet blocked = accumulate(r, terms, map, rho, w, rb, re, folds, rows);
    EXPECT_EQ(blocked.rows, kMismatchChannels * (re - rb));
    for (int f = 0; f < folds; ++f)
      EXPECT_LT(relativeDifference(blocked.G[f], blocked.b[f], blocked.yy[f], held.G[f], held.b[f],
                                   held.yy[f]),
                1e-12)
          << "fold " << f << ", blocks of " << rows << " rows";
  }
}

}  // namespace
}  // namespace graftnav
