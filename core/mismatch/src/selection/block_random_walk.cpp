#include "graftnav/mismatch/block_random_walk.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/QR>

namespace graftnav {

Eigen::MatrixXd blockRandomWalkCovariance(int blocks) {
  Eigen::MatrixXd K(blocks, blocks);
  for (int a = 0; a < blocks; ++a)
    for (int b = 0; b < blocks; ++b) K(a, b) = a == b ? a + 1.0 / 3.0 : std::min(a, b) + 0.5;
  return K;
}

Eigen::MatrixXd replayedRandomWalkCovariance(int blocks, const ReplayTiling& tiling, int nodes) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(blocks, blocks);
  if (!(tiling.period_s > 0.0) || !(tiling.block_s > 0.0) || nodes < 1) return K;
  const double T = tiling.period_s;
  // Position in the record (block units) at each node of each block.
  Eigen::MatrixXd pos(blocks, nodes);
  for (int b = 0; b < blocks; ++b)
    for (int i = 0; i < nodes; ++i) {
      const double u = tiling.start_s + (b + (i + 0.5) / nodes) * tiling.block_s;
      const double tile = std::floor(u / T);
      const double tau = u - tile * T;
      const bool forward = static_cast<long>(tile) % 2 == 0;
      pos(b, i) = (forward ? tau : T - tau) / tiling.block_s;
    }
  for (int a = 0; a < blocks; ++a)
    for (int b = a; b < blocks; ++b) {
      double acc = 0.0;
      for (int i = 0; i < nodes; ++i)
        for (int j = 0; j < nodes; ++j) acc += std::min(pos(a, i), pos(b, j));
      K(a, b) = K(b, a) = acc / (nodes * nodes);
    }
  return K;
}

namespace {

// -2 x the REML log-likelihood (constants dropped) at covariance V.
double remlDeviance(const Eigen::VectorXd& y, const Eigen::MatrixXd& X, const Eigen::MatrixXd& V) {
  const Eigen::LLT<Eigen::MatrixXd> llt(V);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  const Eigen::MatrixXd ViX = llt.solve(X);
  const Eigen::VectorXd Viy = llt.solve(y);
  const Eigen::LLT<Eigen::MatrixXd> lx(X.transpose() * ViX);
  if (lx.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd beta = lx.solve(X.transpose() * Viy);
  const Eigen::VectorXd r = y - X * beta;
  const Eigen::MatrixXd L = llt.matrixL();
  const Eigen::MatrixXd Lx = lx.matrixL();
  const double logdetV = 2.0 * L.diagonal().array().log().sum();
  const double logdetX = 2.0 * Lx.diagonal().array().log().sum();
  return logdetV + logdetX + r.dot(llt.solve(r));
}

}  // namespace

double remlBlockRandomWalk(const std::vector<Eigen::VectorXd>& y,
                           const std::vector<Eigen::MatrixXd>& X, double white_var,
                           const Eigen::MatrixXd& K) {
  if (y.empty() || y.size() != X.size() || !(white_var > 0.0)) return 0.0;
  const int B = static_cast<int>(y[0].size());
  if (K.rows() != B || K.cols() != B) return 0.0;
  int dof = 0;
  for (std::size_t c = 0; c < y.size(); ++c) {
    const int p = static_cast<int>(X[c].cols());
    if (y[c].size() != B || X[c].rows() != B || B - p < 1) return 0.0;
    if (Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(X[c]).rank() < p) return 0.0;
    dof += B - p;
  }
  if (dof < 3) return 0.0;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(B, B);
  const auto deviance = [&](double q) {
    double d = 0.0;
    for (std::size_t c = 0; c < y.size(); ++c) d += remlDeviance(y[c], X[c], white_var * I + q * K);
    return d;
  };
  double best_q = 0.0;
  double best = deviance(0.0);
  // From 1e-4 x white_var up by 10^(1 / 18) ~ 1.137 per step, through 1e5 x white_var and on while
  // the deviance still falls (a wander far above the white noise, e.g. a quiet residual).
  const double ratio = std::pow(10.0, 1.0 / 18.0);
  double q = 1e-4 * white_var;
  for (int k = 0; k < 1000; ++k, q *= ratio) {
    const double d = deviance(q);
    if (d < best) {
      best = d;
      best_q = q;
    } else if (q > 1e5 * white_var) {
      break;
    }
  }
  return best_q;
}

}  // namespace graftnav
