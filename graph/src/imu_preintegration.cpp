#include "graftnav/graph/imu_preintegration.h"

#include <Eigen/Cholesky>
#include <stdexcept>
#include <string>

#include "graftnav/nav/rotation.h"

namespace graftnav {

ImuPreintegration::ImuPreintegration(const Eigen::Vector3d& bg_lin_rad_s,
                                     const Eigen::Vector3d& ba_lin_m_s2,
                                     const PreintegrationNoise& noise)
    : noise_(noise) {
  if (!(noise.arw_rad_sqrt_s >= 0.0) || !(noise.vrw_m_s_sqrt_s >= 0.0)) {
    throw std::invalid_argument("ImuPreintegration: negative or NaN ARW/VRW");
  }
  resetTo(bg_lin_rad_s, ba_lin_m_s2);
}

void ImuPreintegration::resetTo(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba) {
  bg_lin_ = bg;
  ba_lin_ = ba;
  dt_s_ = 0.0;
  dR_.setIdentity();
  dv_.setZero();
  dp_.setZero();
  m2_.setZero();
  dR_dbg_.setZero();
  dv_dbg_.setZero();
  dv_dba_.setZero();
  dp_dbg_.setZero();
  dp_dba_.setZero();
  with_scale_ = false;
  scale_lin_ = ImuScaleFactors();
  dR_dsg_.setZero();
  dv_dsg_.setZero();
  dv_dsa_.setZero();
  dp_dsg_.setZero();
  dp_dsa_.setZero();
  cov_.setZero();
}

void ImuPreintegration::correct(const ImuSample& s, Eigen::Vector3d* dtheta,
                                Eigen::Vector3d* dvel) const {
  *dtheta = s.dtheta_rad - bg_lin_ * s.dt_s;
  *dvel = s.dvel_m_s - ba_lin_ * s.dt_s;
  if (!with_scale_) return;
  *dtheta = dtheta->cwiseQuotient(Eigen::Vector3d::Ones() + scale_lin_.gyro);
  *dvel = dvel->cwiseQuotient(Eigen::Vector3d::Ones() + scale_lin_.accel);
}

void ImuPreintegration::propagateInput(double dt, const Eigen::Matrix3d& G_th,
                                       const Eigen::Matrix3d& G_v, const Eigen::Vector3d& dth,
                                       const Eigen::Vector3d& dvb, const Eigen::Vector3d& dv_fb,
                                       const Eigen::Matrix3d& expPhiT, const Eigen::Matrix3d& Jr,
                                       Eigen::Matrix3d* dR_dx, Eigen::Matrix3d* dv_dx,
                                       Eigen::Matrix3d* dp_dx) const {
  const Eigen::Matrix3d da =
      -dR_ * skew(dv_fb) * *dR_dx + dR_ * (G_v + 0.5 * (skew(dth) * G_v - skew(dvb) * G_th));
  *dp_dx += *dv_dx * dt + 0.5 * dt * da;
  *dv_dx += da;
  *dR_dx = expPhiT * *dR_dx + Jr * G_th;
}

void ImuPreintegration::propagateScaledJacobians(double dt, const Eigen::Vector3d& dth,
                                                 const Eigen::Vector3d& dvb,
                                                 const Eigen::Vector3d& dv_fb,
                                                 const Eigen::Matrix3d& expPhiT,
                                                 const Eigen::Matrix3d& Jr) {
  const Eigen::Vector3d inv_sg = (Eigen::Vector3d::Ones() + scale_lin_.gyro).cwiseInverse();
  const Eigen::Vector3d inv_sa = (Eigen::Vector3d::Ones() + scale_lin_.accel).cwiseInverse();
  const Eigen::Matrix3d Z = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d dR_dba = Z;  // the accelerometer inputs do not rotate
  Eigen::Matrix3d dR_dsa = Z;
  const Eigen::Matrix3d G_bg = (-dt * inv_sg).asDiagonal();
  const Eigen::Matrix3d G_ba = (-dt * inv_sa).asDiagonal();
  const Eigen::Matrix3d G_sg = (-dth.cwiseProduct(inv_sg)).asDiagonal();
  const Eigen::Matrix3d G_sa = (-dvb.cwiseProduct(inv_sa)).asDiagonal();
  propagateInput(dt, G_bg, Z, dth, dvb, dv_fb, expPhiT, Jr, &dR_dbg_, &dv_dbg_, &dp_dbg_);
  propagateInput(dt, Z, G_ba, dth, dvb, dv_fb, expPhiT, Jr, &dR_dba, &dv_dba_, &dp_dba_);
  propagateInput(dt, G_sg, Z, dth, dvb, dv_fb, expPhiT, Jr, &dR_dsg_, &dv_dsg_, &dp_dsg_);
  propagateInput(dt, Z, G_sa, dth, dvb, dv_fb, expPhiT, Jr, &dR_dsa, &dv_dsa_, &dp_dsa_);
}

void ImuPreintegration::integrate(const ImuSample& prev, const ImuSample& cur) {
  const double dt = cur.dt_s;
  if (!(dt > 0.0)) {
    throw std::invalid_argument("ImuPreintegration::integrate: sample at t=" +
                                std::to_string(cur.t_s) + " has dt=" + std::to_string(dt));
  }
  Eigen::Vector3d dth, dvb, pth, pdv;
  correct(cur, &dth, &dvb);
  correct(prev, &pth, &pdv);
  const Eigen::Vector3d dv_fb =
      dvb + 0.5 * dth.cross(dvb) + (pth.cross(dvb) + pdv.cross(dth)) / 12.0;
  const Eigen::Vector3d phi = dth + pth.cross(dth) / 12.0;
  const Eigen::Vector3d a = dR_ * dv_fb;

  // Error-state transition (order p, v, phi) and noise input, with the rotation before the step.
  const Eigen::Matrix3d dR_skew_dv = dR_ * skew(dvb);
  const Eigen::Matrix3d expPhiT = dcmFromRotationVector(phi).transpose();
  const Eigen::Matrix3d Jr = rightJacobianSO3(phi);
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(kP, kV) = dt * Eigen::Matrix3d::Identity();
  A.block<3, 3>(kP, kR) = -0.5 * dt * dR_skew_dv;
  A.block<3, 3>(kV, kR) = -dR_skew_dv;
  A.block<3, 3>(kR, kR) = expPhiT;
  const double var_th = noise_.arw_rad_sqrt_s * noise_.arw_rad_sqrt_s * dt;
  const double var_v = noise_.vrw_m_s_sqrt_s * noise_.vrw_m_s_sqrt_s * dt;
  Matrix9d BQBt = Matrix9d::Zero();
  const Eigen::Matrix3d RRt = dR_ * dR_.transpose();  // = I; kept explicit for clarity of B
  BQBt.block<3, 3>(kP, kP) = 0.25 * dt * dt * var_v * RRt;
  BQBt.block<3, 3>(kP, kV) = 0.5 * dt * var_v * RRt;
  BQBt.block<3, 3>(kV, kP) = 0.5 * dt * var_v * RRt;
  BQBt.block<3, 3>(kV, kV) = var_v * RRt;
  BQBt.block<3, 3>(kR, kR) = var_th * Jr * Jr.transpose();
  // lazyProduct: coefficient-wise 9x9 products (Eigen would otherwise call its GEMM kernel).
  const Matrix9d AP = A.lazyProduct(cov_);
  cov_ = AP.lazyProduct(A.transpose()) + BQBt;

  if (with_scale_) {
    propagateScaledJacobians(dt, dth, dvb, dv_fb, expPhiT, Jr);
  } else {
    propagateBiasJacobians(dt, dth, dv_fb, dR_skew_dv, expPhiT, Jr);
  }

  // Increments.
  const double tau_mid = dt_s_ + 0.5 * dt;
  m2_ += tau_mid * tau_mid * a;
  dp_ += dv_ * dt + 0.5 * dt * a;
  dv_ += a;
  dR_ = dR_ * dcmFromRotationVector(phi);
  dt_s_ += dt;
}

void ImuPreintegration::propagateBiasJacobians(double dt, const Eigen::Vector3d& dth,
                                               const Eigen::Vector3d& dv_fb,
                                               const Eigen::Matrix3d& dR_skew_dv,
                                               const Eigen::Matrix3d& expPhiT,
                                               const Eigen::Matrix3d& Jr) {
  // Bias Jacobians (p uses the old v and R Jacobians, v the old R Jacobian). da/dbg has the
  // rotation of dR and the 1/2 dtheta x dv term of the sculling correction:
  //   da/dbg = -dR [dv_fb]x dR_dbg + 1/2 dt dR [dv]x,   da/dba = -dt dR (1/2 dtheta x dv: O(dt^2)).
  const Eigen::Matrix3d da_dbg = -dR_ * skew(dv_fb) * dR_dbg_ + 0.5 * dt * dR_skew_dv;
  const Eigen::Matrix3d da_dba = -dt * dR_ - 0.5 * dt * dR_ * skew(dth);
  dp_dbg_ += dv_dbg_ * dt + 0.5 * dt * da_dbg;
  dp_dba_ += dv_dba_ * dt + 0.5 * dt * da_dba;
  dv_dbg_ += da_dbg;
  dv_dba_ += da_dba;
  dR_dbg_ = expPhiT * dR_dbg_ - Jr * dt;
}

void ImuPreintegration::reintegrate(const ImuSeries& imu, size_t begin, size_t end,
                                    const Eigen::Vector3d& bg_rad_s,
                                    const Eigen::Vector3d& ba_m_s2) {
  if (begin >= end || end > imu.size()) {
    throw std::invalid_argument("ImuPreintegration::reintegrate: bad sample range [" +
                                std::to_string(begin) + ", " + std::to_string(end) + ") of " +
                                std::to_string(imu.size()));
  }
  reintegrate(imu.data() + begin, end - begin, begin > 0 ? &imu[begin - 1] : nullptr, bg_rad_s,
              ba_m_s2);
}

void ImuPreintegration::reintegrate(const ImuSample* samples, size_t count, const ImuSample* before,
                                    const Eigen::Vector3d& bg_rad_s,
                                    const Eigen::Vector3d& ba_m_s2) {
  if (count == 0) {
    throw std::invalid_argument("ImuPreintegration::reintegrate: no samples in the interval");
  }
  resetTo(bg_rad_s, ba_m_s2);
  integrate(before ? *before : samples[0], samples[0]);
  for (size_t k = 1; k < count; ++k) integrate(samples[k - 1], samples[k]);
}

void ImuPreintegration::reintegrate(const ImuSample* samples, size_t count, const ImuSample* before,
                                    const Eigen::Vector3d& bg_rad_s, const Eigen::Vector3d& ba_m_s2,
                                    const ImuScaleFactors& scale) {
  if (count == 0) {
    throw std::invalid_argument("ImuPreintegration::reintegrate: no samples in the interval");
  }
  if (!((Eigen::Vector3d::Ones() + scale.gyro).minCoeff() > 0.0) ||
      !((Eigen::Vector3d::Ones() + scale.accel).minCoeff() > 0.0)) {
    throw std::invalid_argument("ImuPreintegration::reintegrate: scale factor <= -1 or NaN");
  }
  resetTo(bg_rad_s, ba_m_s2);
  with_scale_ = true;
  scale_lin_ = scale;
  integrate(before ? *before : samples[0], samples[0]);
  for (size_t k = 1; k < count; ++k) integrate(samples[k - 1], samples[k]);
}

ImuPreintegration::Matrix9d ImuPreintegration::sqrtInformation() const {
  Eigen::LLT<Matrix9d> llt(cov_);
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error(
        "ImuPreintegration::sqrtInformation: covariance not positive definite"
        " (zero ARW/VRW?) over dt=" +
        std::to_string(dt_s_));
  }
  Matrix9d Linv = llt.matrixL().solve(Matrix9d::Identity());
  return Linv;
}

Eigen::Matrix3d ImuPreintegration::correctedDeltaR(const Eigen::Vector3d& bg) const {
  return dR_ * dcmFromRotationVector(dR_dbg_ * (bg - bg_lin_));
}

Eigen::Vector3d ImuPreintegration::correctedDeltaV(const Eigen::Vector3d& bg,
                                                   const Eigen::Vector3d& ba) const {
  return dv_ + dv_dbg_ * (bg - bg_lin_) + dv_dba_ * (ba - ba_lin_);
}

Eigen::Vector3d ImuPreintegration::correctedDeltaP(const Eigen::Vector3d& bg,
                                                   const Eigen::Vector3d& ba) const {
  return dp_ + dp_dbg_ * (bg - bg_lin_) + dp_dba_ * (ba - ba_lin_);
}

Eigen::Vector3d ImuPreintegration::rotationCorrection(const Eigen::Vector3d& bg,
                                                      const ImuScaleFactors& s) const {
  return dR_dbg_ * (bg - bg_lin_) + dR_dsg_ * (s.gyro - scale_lin_.gyro);
}

Eigen::Matrix3d ImuPreintegration::correctedDeltaR(const Eigen::Vector3d& bg,
                                                   const ImuScaleFactors& s) const {
  return dR_ * dcmFromRotationVector(rotationCorrection(bg, s));
}

Eigen::Vector3d ImuPreintegration::correctedDeltaV(const Eigen::Vector3d& bg,
                                                   const Eigen::Vector3d& ba,
                                                   const ImuScaleFactors& s) const {
  return correctedDeltaV(bg, ba) + dv_dsg_ * (s.gyro - scale_lin_.gyro) +
         dv_dsa_ * (s.accel - scale_lin_.accel);
}

Eigen::Vector3d ImuPreintegration::correctedDeltaP(const Eigen::Vector3d& bg,
                                                   const Eigen::Vector3d& ba,
                                                   const ImuScaleFactors& s) const {
  return correctedDeltaP(bg, ba) + dp_dsg_ * (s.gyro - scale_lin_.gyro) +
         dp_dsa_ * (s.accel - scale_lin_.accel);
}

}  // namespace graftnav
