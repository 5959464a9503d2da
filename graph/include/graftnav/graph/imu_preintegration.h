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
//
// With scale factors (the EKF's sensor model, filters/ins_error_model.h: each increment corrected
// as (raw - b dt) / (1 + s) per axis), the samples are corrected by the linearization scales
// sg_lin, sa_lin too, and first-order Jacobians d(dR, dv, dp)/d(sg, sa) are carried the same way
// as the bias ones: a parameter x entering the corrected increments as d(dtheta')/dx = G_th,
// d(dv')/dx = G_v propagates as
//   da/dx  = -dR [dv_fb]x dR_dx + dR (G_v + 1/2 ([dtheta']x G_v - [dv']x G_th))
//   dp_dx += dv_dx dt + 1/2 da/dx dt,  dv_dx += da/dx,  dR_dx = Exp(phi)^T dR_dx + Jr(phi) G_th
// with G_th = -dt diag(1/(1+sg)) for bg, -diag(dtheta') for sg, and likewise for the accelerometer.

#include <Eigen/Core>

#include "graftnav/nav/types.h"

namespace graftnav {

struct PreintegrationNoise {
  double arw_rad_sqrt_s = 0.0;
  double vrw_m_s_sqrt_s = 0.0;
};

// Gyro and accelerometer scale factors per axis (fractions), as the EKF's sensor model.
struct ImuScaleFactors {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
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
  // The same with the samples also corrected by the scale factors `scale`, whose Jacobians are
  // then carried (withScale() true until the next reintegrate without them).
  void reintegrate(const ImuSample* samples, size_t count, const ImuSample* before,
                   const Eigen::Vector3d& bg_rad_s, const Eigen::Vector3d& ba_m_s2,
                   const ImuScaleFactors& scale);

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
  bool withScale() const { return with_scale_; }
  const ImuScaleFactors& scaleLin() const { return scale_lin_; }
  const Eigen::Matrix3d& dR_dsg() const { return dR_dsg_; }
  const Eigen::Matrix3d& dv_dsg() const { return dv_dsg_; }
  const Eigen::Matrix3d& dv_dsa() const { return dv_dsa_; }
  const Eigen::Matrix3d& dp_dsg() const { return dp_dsg_; }
  const Eigen::Matrix3d& dp_dsa() const { return dp_dsa_; }
  const Matrix9d& covariance() const { return cov_; }
  // L^-1 with covariance = L L^T (so that r_whitened = sqrtInformation() * r).
  Matrix9d sqrtInformation() const;

  // Bias-corrected increments (first order in bias - bias_lin).
  Eigen::Matrix3d correctedDeltaR(const Eigen::Vector3d& bg) const;
  Eigen::Vector3d correctedDeltaV(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const;
  Eigen::Vector3d correctedDeltaP(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) const;
  // The same, first order also in scale - scale_lin (withScale() only).
  Eigen::Vector3d rotationCorrection(const Eigen::Vector3d& bg, const ImuScaleFactors& s) const;
  Eigen::Matrix3d correctedDeltaR(const Eigen::Vector3d& bg, const ImuScaleFactors& s) const;
  Eigen::Vector3d correctedDeltaV(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba,
                                  const ImuScaleFactors& s) const;
  Eigen::Vector3d correctedDeltaP(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba,
                                  const ImuScaleFactors& s) const;

 private:
  void resetTo(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba);
  // Sample pair corrected by the linearization biases (and scales, withScale()).
  void correct(const ImuSample& s, Eigen::Vector3d* dtheta, Eigen::Vector3d* dvel) const;
  // Bias Jacobians over one step without scale factors.
  void propagateBiasJacobians(double dt, const Eigen::Vector3d& dth, const Eigen::Vector3d& dv_fb,
                              const Eigen::Matrix3d& dR_skew_dv, const Eigen::Matrix3d& expPhiT,
                              const Eigen::Matrix3d& Jr);
  // Scale-factor Jacobians (and the bias ones, which the scales divide) over one step, before
  // the increments move; dth, dvb the corrected step, dv_fb its sculling-corrected velocity.
  void propagateScaledJacobians(double dt, const Eigen::Vector3d& dth, const Eigen::Vector3d& dvb,
                                const Eigen::Vector3d& dv_fb, const Eigen::Matrix3d& expPhiT,
                                const Eigen::Matrix3d& Jr);
  // One parameter's Jacobians d(dR, dv, dp)/dx given its input derivatives G_th, G_v.
  void propagateInput(double dt, const Eigen::Matrix3d& G_th, const Eigen::Matrix3d& G_v,
                      const Eigen::Vector3d& dth, const Eigen::Vector3d& dvb,
                      const Eigen::Vector3d& dv_fb, const Eigen::Matrix3d& expPhiT,
                      const Eigen::Matrix3d& Jr, Eigen::Matrix3d* dR_dx, Eigen::Matrix3d* dv_dx,
                      Eigen::Matrix3d* dp_dx) const;

  Eigen::Vector3d bg_lin_, ba_lin_;
  PreintegrationNoise noise_;
  double dt_s_ = 0.0;
  Eigen::Matrix3d dR_;
  Eigen::Vector3d dv_, dp_, m2_;
  Eigen::Matrix3d dR_dbg_, dv_dbg_, dv_dba_, dp_dbg_, dp_dba_;
  bool with_scale_ = false;
  ImuScaleFactors scale_lin_;
  Eigen::Matrix3d dR_dsg_, dv_dsg_, dv_dsa_, dp_dsg_, dp_dsa_;
  Matrix9d cov_;
};

}  // namespace graftnav
