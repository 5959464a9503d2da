#pragma once
// The Kalman measurement update of the EKF on an N-state error covariance with M measurement
// rows: N = 21 (ins_error_model.h), or 22 with the odometer scale state; M = 3 for GNSS, 1 to 3
// for the vehicle-frame velocity. Joseph form, symmetrized, with a gate on the innovation's
// squared Mahalanobis norm decided by the caller.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace graftnav {

// Symmetric, with a positive floor on the diagonal.
template <int N>
void symmetrizeCovariance(Eigen::Matrix<double, N, N>& P) {
  P = 0.5 * (P + P.transpose()).eval();
  for (int i = 0; i < N; ++i) P(i, i) = std::max(P(i, i), 1e-300);
}

// z = h(x) - y with Jacobian H, measurement variances r_diag. accept(d2) decides from the
// squared Mahalanobis norm d2 = z^T S^-1 z; when it refuses, nothing changes and false is
// returned. Otherwise P becomes the posterior and *dx the correction K z. Throws
// std::runtime_error naming t_s when S is not positive definite.
template <int N, int M, typename Accept>
bool josephUpdate(Eigen::Matrix<double, N, N>& P, const Eigen::Matrix<double, M, 1>& z,
                  const Eigen::Matrix<double, M, N>& H, const Eigen::Matrix<double, M, 1>& r_diag,
                  double t_s, Accept&& accept, Eigen::Matrix<double, N, 1>* dx) {
  const Eigen::Matrix<double, N, M> PHt = P * H.transpose();
  Eigen::Matrix<double, M, M> S = H * PHt;
  S.diagonal() += r_diag;
  const Eigen::LLT<Eigen::Matrix<double, M, M>> llt(S);
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error("GnssInsEkf::update: innovation covariance not positive at t=" +
                             std::to_string(t_s));
  }
  const double d2 = z.dot(llt.solve(z));
  if (!accept(d2)) return false;
  const Eigen::Matrix<double, N, M> K = llt.solve(PHt.transpose()).transpose();
  *dx = K * z;
  Eigen::Matrix<double, N, N> IKH = Eigen::Matrix<double, N, N>::Identity();
  IKH.noalias() -= K * H;
  const Eigen::Matrix<double, N, N> tmp = IKH * P;
  P.noalias() = tmp * IKH.transpose();
  P.noalias() += K * r_diag.asDiagonal() * K.transpose();
  symmetrizeCovariance<N>(P);
  return true;
}

}  // namespace graftnav
