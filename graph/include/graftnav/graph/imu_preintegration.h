#pragma once
// IMU preintegration between two graph nodes i and j, in the body frame of node i (b_i).
// Derivation, residual and Jacobians: docs/fgo.md.
//
// From samples k = 1..K (increments dtheta_k, dv_k over dt_k) corrected by the linearization
// biases bg_lin, ba_lin, with the same two-sample coning/sculling as core's Strapdown:
//   dv_fb_k = dv'_k + 1/2 dtheta'_k x dv'_k + 1/12 (dtheta'_{k-1} x dv'_k + dv'_{k-1} x dtheta'_k)
//   phi_k   = dtheta'_k + 1/12 dtheta'_{k-1} x dtheta'_k
//   a_k     = dR_{k-1} dv_fb_k                      (velocity increment resolved in b_i)
//   dp_k    = dp_{k-1} + dv_{k-1} dt_k + 1/2 a_k dt_k,  dv_k = dv_{k-1} + a_k,
//   dR_k    = dR_{k-1} Exp(phi_k)
// and two moments used by the Earth-rotation correction of the factor:
//   m1 = int_0^T tau a(tau) dtau        = T dv - dp         (exact for the scheme above)
//   c  = int_0^T (T - tau) tau a(tau) dtau = T m1 - sum tau_mid^2 a_k
// Error state (residual order of the factor): [dp, dv, dphi] with dR_true = dR Exp(dphi).
// Covariance propagation from ARW (rad/sqrt(s)) and VRW (m/s/sqrt(s)); first-order bias
// Jacobians d(dR, dv, dp)/d(bg, ba) for bias correction without re-integration.

#include <Eigen/Core>

#include "graftnav/nav/types.h"

namespace graftnav {

struct PreintegrationNoise {
  double arw_rad_sqrt_s = 0.0;
  double vrw_m_s_sqrt_s = 0.0;
};

class ImuPreintegration {
 public:
  using Matrix9d = Eigen::Matrix<double, 9, 9>;
  static constexpr int kP = 0;  // residual / error-state block offsets
  static constexpr int kV = 3;
  static constexpr int kR = 6;

  ImuPreintegration(const Eigen::Vector3d& bg_lin_rad_s, const Eigen::Vector3d& ba_lin_m_s2,
                    const PreintegrationNoise& noise);

  // Adds one sample; `prev` is the sample before it (for coning/sculling; pass `cur` itself when
  // there is none). Both are raw (uncorrected) IMU samples.
  void integrate(const ImuSample& prev, const ImuSample& cur);

  // Re-integrates samples [begin, end) of `imu` about a new linearization bias. `begin` > 0 uses
  // imu[begin-1] as the coning/sculling memory.
  void reintegrate(const ImuSeries& imu, size_t begin, size_t end, const Eigen::Vector3d& bg_rad_s,
                   const Eigen::Vector3d& ba_m_s2);
  // The same over `count` consecutive samples at `samples`; `before` is the sample before the
  // first (coning/sculling memory), null when there is none.
  void reintegrate(const ImuSample* samples, size_t count, const ImuSample* before,
                   const Eigen::Vector3d& bg_rad_s, const Eigen::Vector3d& ba_m_s2);

  double dt_s() const { return dt_s_; }
  const Eigen::Matrix3d& deltaR() const { return dR_; }
  const Eigen::Vector3d& deltaV() const { return dv_; }
  const Eigen::Vector3d& deltaP() const { return dp_; }
  Eigen::Vector3d firstMoment() const { return dt_s_ * dv_ - dp_; }
  Eigen::Vector3d coriolisMoment() const { return dt_s_ * firstMoment() - m2_; }
  const Eigen::Vector3d& bgLin() const { return bg_lin_; }
  const Eigen::Vector3d& baLin() const { return ba_lin_; }
  const Eigen::Matrix3d& dR_dbg() const { return dR_dbg_; }
  const Eigen::Matrix3d& dv_dbg() const { return dv_dbg_; }
  const Eigen::Matrix3d& dv_dba() const { return dv_dba_; }
  const Eigen::Matrix3d& dp_dbg() const { return dp_dbg_; }
  const Eigen::Matrix3d& dp_dba() const { return dp_dba_; }
  const Matrix9d& covariance() const { return cov_; }
  // L^-1 with covariance = L L^T (so that r_whitened = sqrtInformation() * r).
  Matrix9d sqrtInformation() const;

  // Bias-corrected increments (first order in bias - bias_lin).
  Eigen::Matrix3d correctedDeltaR(const Eigen::Vector3d& bg) const;
  Eigen::Vector3d correctedDeltaV(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const;
  Eigen::Vector3d correctedDeltaP(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const;

 private:
  void resetTo(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba);

  Eigen::Vector3d bg_lin_, ba_lin_;
  PreintegrationNoise noise_;
  double dt_s_ = 0.0;
  Eigen::Matrix3d dR_;
  Eigen::Vector3d dv_, dp_, m2_;
  Eigen::Matrix3d dR_dbg_, dv_dbg_, dv_dba_, dp_dbg_, dp_dba_;
  Matrix9d cov_;
};

}  // namespace graftnav
