#pragma once
// Internal to the mismatch module: the residual blocks of the joint time-offset fit
// (joint_fit.h), in a header of their own so that their analytic Jacobian can be tested against a
// numerical one (core/mismatch/tests/test_mismatch_chunk_cost.cpp).
#include <ceres/ceres.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/nav/types.h"

namespace graftnav::joint_fit_detail {

struct ColumnRef {
  int param;                // index into theta
  const double* u;          // regressor values on this channel, every bin
  Eigen::VectorXd du;       // its time derivative
  Eigen::VectorXd u_whole;  // u's storage for a column held as a stretch (else empty)
};

// Everything the residual blocks share.
struct JointData {
  const Eigen::MatrixXd* r = nullptr;
  const CumulativeImu* cum = nullptr;
  GridSpec grid;
  Eigen::MatrixXd X;      // n x 6 unshifted reference bin means
  Eigen::MatrixXd K, dK;  // n x 6 fixed-term contribution and its derivative
  double pivot = 0.0;     // the regressors' own shift: theirs in the model is tau - pivot
  std::array<std::vector<ColumnRef>, kMismatchChannels> cols;
  Eigen::Matrix<double, 6, 1> rho, w;
  int P = 0;

  // Error e = r - model at bin i, its derivatives in theta (6 x P, row-major into de_dth) and tau.
  void error(int i, const double* theta, double tau, double* e, double* de_dth,
             double* de_dtau) const {
    const double a = grid.binStart(i), b = grid.binStart(i + 1), h = grid.bin_s;
    const Vector6d xs = (cum->at(b - tau) - cum->at(a - tau)) / h;
    Vector6d dxs;
    if (de_dtau) dxs = -(cum->rateAt(b - tau) - cum->rateAt(a - tau)) / h;
    const double dtau = tau - pivot;
    for (int c = 0; c < kMismatchChannels; ++c) {
      double m = xs(c) - X(i, c) + K(i, c) - dtau * dK(i, c);
      double dm_dtau = de_dtau ? dxs(c) - dK(i, c) : 0.0;
      if (de_dth) std::fill(de_dth + c * P, de_dth + (c + 1) * P, 0.0);
      for (const ColumnRef& col : cols[c]) {
        const double u = col.u[i], du = col.du(i);
        m += theta[col.param] * (u - dtau * du);
        dm_dtau -= theta[col.param] * du;
        if (de_dth) de_dth[c * P + col.param] = -(u - dtau * du);
      }
      e[c] = (*r)(i, c) - m;
      if (de_dtau) de_dtau[c] = -dm_dtau;
    }
  }
};

// AR(1)-whitened residuals of bins [i0, i1): z_i = w_c (e_i - rho_c e_{i-1}); the record's first
// bin gets w_c sqrt(1 - rho_c^2) e_0 (as in the selection's prewhitening).
class ChunkCost final : public ceres::CostFunction {
 public:
  ChunkCost(const JointData* d, int i0, int i1) : d_(d), i0_(i0), i1_(i1) {
    set_num_residuals(kMismatchChannels * (i1 - i0));
    mutable_parameter_block_sizes()->push_back(d->P);
    mutable_parameter_block_sizes()->push_back(1);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* theta = parameters[0];
    const double tau = parameters[1][0];
    const int P = d_->P;
    const bool jac = jacobians != nullptr;
    double e_prev[6], e_cur[6], de_tau_prev[6], de_tau_cur[6];
    std::vector<double> dth_prev(jac ? 6 * P : 0), dth_cur(jac ? 6 * P : 0);
    const bool has_prev = i0_ > 0;
    if (has_prev)
      d_->error(i0_ - 1, theta, tau, e_prev, jac ? dth_prev.data() : nullptr,
                jac ? de_tau_prev : nullptr);
    for (int i = i0_; i < i1_; ++i) {
      d_->error(i, theta, tau, e_cur, jac ? dth_cur.data() : nullptr, jac ? de_tau_cur : nullptr);
      const bool first = i == 0;
      for (int c = 0; c < kMismatchChannels; ++c) {
        const double p = d_->rho(c), w = d_->w(c);
        const int row = (i - i0_) * kMismatchChannels + c;
        const double sc = first ? w * std::sqrt(std::max(0.0, 1.0 - p * p)) : w;
        const double pp = first ? 0.0 : p;
        residuals[row] = sc * e_cur[c] - (first ? 0.0 : w * pp * e_prev[c]);
        if (jac) {
          if (jacobians[0]) {
            double* J = jacobians[0] + static_cast<std::ptrdiff_t>(row) * P;
            for (int k = 0; k < P; ++k)
              J[k] = sc * dth_cur[c * P + k] - (first ? 0.0 : w * pp * dth_prev[c * P + k]);
          }
          if (jacobians[1])
            jacobians[1][row] = sc * de_tau_cur[c] - (first ? 0.0 : w * pp * de_tau_prev[c]);
        }
      }
      std::copy(e_cur, e_cur + 6, e_prev);
      if (jac) {
        std::copy(de_tau_cur, de_tau_cur + 6, de_tau_prev);
        dth_prev.swap(dth_cur);
      }
    }
    return true;
  }

 private:
  const JointData* d_;
  int i0_, i1_;
};

}  // namespace graftnav::joint_fit_detail
