#include <cmath>
#include <optional>
#include <vector>

#include <Eigen/Cholesky>

#include "graftnav/mismatch/locate.h"
#include "graftnav/mismatch/wander.h"

namespace graftnav {

namespace {

// The slow wander of each channel of `r`: least squares on a constant plus the hat functions of
// the bias_instability term of that channel's sensor (its knots), evaluated on all bins, record
// mean removed. Also returns the number of fitted columns per channel (for the white-noise share).
Eigen::MatrixXd fitWander(const Eigen::MatrixXd& r, const std::vector<CandidateTerm>& terms,
                          const std::vector<char>& masked, Eigen::Matrix<int, 6, 1>* columns) {
  const int n = static_cast<int>(r.rows());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  columns->setZero();
  for (int c = 0; c < kMismatchChannels; ++c) {
    std::vector<const RegressorColumn*> cols;
    for (const CandidateTerm& t : terms)
      if (t.kind() == TermKind::bias_instability)
        for (const RegressorColumn& col : t.columns)
          if (col.actsOn(c)) cols.push_back(&col);
    if (cols.empty()) continue;
    const int p = static_cast<int>(cols.size()) + 1;
    Eigen::MatrixXd X(n, p);
    for (int i = 0; i < n; ++i) X(i, 0) = masked[i] ? 0.0 : 1.0;
    for (int j = 1; j < p; ++j) X.col(j) = cols[j - 1]->dense(c);
    const Eigen::VectorXd coef = (X.transpose() * X).ldlt().solve(X.transpose() * r.col(c));
    out.col(c) = X.rightCols(p - 1) * coef.tail(p - 1);
    out.col(c).array() -= out.col(c).mean();
    (*columns)(c) = p;
  }
  return out;
}

}  // namespace

Eigen::Vector3d expectedWanderSd(const LabNoiseFigures& lab, double duration_s) {
  const Eigen::Vector3d B = lab.bias_instability, K = lab.rate_random_walk;
  return (2.0 * B.cwiseProduct(B) + K.cwiseProduct(K) * (duration_s / 3.0)).cwiseSqrt();
}

std::vector<WanderCheck> checkWander(const Eigen::MatrixXd& residual,
                                     const std::vector<CandidateTerm>& terms,
                                     const std::optional<LabNoiseFigures>& gyro,
                                     const std::optional<LabNoiseFigures>& accel,
                                     const Eigen::Matrix<double, 6, 1>& bin_variance,
                                     const GridSpec& grid, const std::vector<char>& masked,
                                     Eigen::MatrixXd* within_wander) {
  std::vector<WanderCheck> out;
  const int n = static_cast<int>(residual.rows());
  *within_wander = Eigen::MatrixXd::Zero(n, kMismatchChannels);
  if (!gyro && !accel) return out;
  Eigen::Matrix<int, 6, 1> columns;
  const Eigen::MatrixXd w = fitWander(residual, terms, masked, &columns);
  const double duration_s = n * grid.bin_s;
  for (int c = 0; c < kMismatchChannels; ++c) {
    const std::optional<LabNoiseFigures>& lab = c < 3 ? gyro : accel;
    if (!lab || columns(c) == 0) continue;
    WanderCheck k;
    k.channel = c;
    k.fitted_sd = std::sqrt(w.col(c).squaredNorm() / n);
    // White noise the knots pass: a share columns / n of the per-bin noise variance.
    const double expected = expectedWanderSd(*lab, duration_s)(c % 3);
    k.expected_sd = std::sqrt(expected * expected + bin_variance(c) * columns(c) / n);
    k.limit = kWanderSdQuantile999 * k.expected_sd;
    k.within = k.fitted_sd <= k.limit;
    if (k.within) within_wander->col(c) = w.col(c);
    out.push_back(k);
  }
  return out;
}

}  // namespace graftnav
