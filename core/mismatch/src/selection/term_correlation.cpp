#include "graftnav/mismatch/term_correlation.h"

#include <algorithm>
#include <stdexcept>

#include <Eigen/QR>
#include <Eigen/SVD>

namespace graftnav {
namespace {

// Orthonormal basis of a term's whitened columns, net of the per-channel constant (rows: bins x
// channels, channel-major). Empty when the term has no signal.
Eigen::MatrixXd whitenedBasis(const CandidateTerm& term, const SelectionResult& sel,
                              const std::vector<char>& masked, int n) {
  const int cols = static_cast<int>(term.columns.size());
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n) * kMismatchChannels, cols);
  for (int j = 0; j < cols; ++j) {
    for (int c = 0; c < kMismatchChannels; ++c) {
      if (!term.columns[j].actsOn(c)) continue;
      const Eigen::VectorXd u = term.columns[j].dense(c);
      const double rho = sel.rho(c), sigma = sel.sigma(c) > 0.0 ? sel.sigma(c) : 1.0;
      Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
      int used = 0;
      double mean = 0.0;
      for (int i = 1; i < n && i < u.size(); ++i) {
        if (!masked.empty() && (masked[i] || masked[i - 1])) continue;
        w(i) = (u(i) - rho * u(i - 1)) / sigma;
        mean += w(i);
        ++used;
      }
      if (used == 0) continue;
      mean /= used;
      for (int i = 1; i < n && i < u.size(); ++i)
        if (masked.empty() || !(masked[i] || masked[i - 1])) w(i) -= mean;
      X.block(static_cast<Eigen::Index>(c) * n, j, n, 1) = w;
    }
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  qr.setThreshold(1e-9);
  const int rank = static_cast<int>(qr.rank());
  if (rank == 0) return {};
  Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(X.rows(), rank);
  return Q;
}

}  // namespace

std::vector<TermCorrelation> termCorrelations(const std::vector<CandidateTerm>& terms,
                                              const SelectionResult& selection,
                                              const std::vector<char>& masked) {
  int n = 0;
  std::vector<int> idx;
  for (const TermFit& tf : selection.selected) {
    if (tf.term < 0 || tf.term >= static_cast<int>(terms.size()))
      throw std::invalid_argument("termCorrelations: term index " + std::to_string(tf.term) +
                                  " out of range");
    if (terms[tf.term].fixed()) continue;
    idx.push_back(tf.term);
    for (const RegressorColumn& col : terms[tf.term].columns)
      for (const Eigen::VectorXd& v : col.channel) n = std::max(n, static_cast<int>(v.size()));
  }
  std::vector<Eigen::MatrixXd> basis;
  for (int t : idx) basis.push_back(whitenedBasis(terms[t], selection, masked, n));
  std::vector<TermCorrelation> out;
  for (std::size_t a = 0; a < idx.size(); ++a)
    for (std::size_t b = a + 1; b < idx.size(); ++b) {
      TermCorrelation c;
      c.term_a = terms[idx[a]].key();
      c.term_b = terms[idx[b]].key();
      if (basis[a].size() > 0 && basis[b].size() > 0) {
        const Eigen::MatrixXd M = basis[a].transpose() * basis[b];
        c.canonical = std::min(1.0, Eigen::JacobiSVD<Eigen::MatrixXd>(M).singularValues()(0));
      }
      out.push_back(c);
    }
  return out;
}

TermCorrelation mostCorrelatedWith(const std::vector<TermCorrelation>& correlations,
                                   const TermKey& key) {
  TermCorrelation best;
  for (const TermCorrelation& c : correlations) {
    if (c.term_a != key && c.term_b != key) continue;
    if (c.canonical > best.canonical) {
      best.term_a = key;
      best.term_b = c.term_a == key ? c.term_b : c.term_a;
      best.canonical = c.canonical;
    }
  }
  return best;
}

}  // namespace graftnav
