#include "graftnav/filters/ins_error_model.h"

#include <cmath>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

using namespace ekf;

ImuSample correctImuSample(const ImuSample& raw, const ImuErrorEstimate& e) {
  ImuSample s = raw;
  s.dtheta_rad = (raw.dtheta_rad - e.gyro_bias_rad_s * raw.dt_s)
                     .cwiseQuotient(Eigen::Vector3d::Ones() + e.gyro_scale);
  s.dvel_m_s = (raw.dvel_m_s - e.accel_bias_m_s2 * raw.dt_s)
                   .cwiseQuotient(Eigen::Vector3d::Ones() + e.accel_scale);
  return s;
}

ErrorCov errorDynamics(const NavState& s, const Eigen::Vector3d& omega_ib_b,
                       const Eigen::Vector3d& f_b, const ImuProfile& profile) {
  ErrorCov F = ErrorCov::Zero();
  const Eigen::Matrix3d C_nb = s.q_nb.toRotationMatrix();
  const Eigen::Vector3d w_ie = earth::omega_ie_n(s.pos.lat_rad);
  const Eigen::Vector3d w_en = earth::omega_en_n(s.pos, s.v_n);
  const earth::Radii r = earth::radiiOfCurvature(s.pos.lat_rad);
  const double R = std::sqrt(r.meridian_m * r.prime_vertical_m) + s.pos.h_m;
  const double g = earth::gravityMagnitude(s.pos);
  const Eigen::Vector3d f_n = C_nb * f_b;

  F.block<3, 3>(kPos, kPos) = -skew(w_en);
  F.block<3, 3>(kPos, kVel).setIdentity();
  F.block<3, 3>(kVel, kPos) = (g / R) * Eigen::Vector3d(-1.0, -1.0, 2.0).asDiagonal();
  F.block<3, 3>(kVel, kVel) = -skew(2.0 * w_ie + w_en);
  F.block<3, 3>(kVel, kAtt) = skew(f_n);
  F.block<3, 3>(kVel, kAccelBias) = C_nb;
  F.block<3, 3>(kVel, kAccelScale) = C_nb * f_b.asDiagonal();
  F.block<3, 3>(kAtt, kAtt) = -skew(w_ie + w_en);
  F.block<3, 3>(kAtt, kGyroBias) = -C_nb;
  F.block<3, 3>(kAtt, kGyroScale) = -C_nb * omega_ib_b.asDiagonal();
  auto decay = [&](int off, double T) {
    if (T > 0.0 && std::isfinite(T))
      F.block<3, 3>(off, off) = -(1.0 / T) * Eigen::Matrix3d::Identity();
  };
  decay(kGyroBias, profile.gyro_bias_corr_time_s);
  decay(kAccelBias, profile.accel_bias_corr_time_s);
  decay(kGyroScale, profile.scale_corr_time_s);
  decay(kAccelScale, profile.scale_corr_time_s);
  return F;
}

ErrorState continuousNoiseDensity(const ImuProfile& p) {
  ErrorState q = ErrorState::Zero();
  auto gm = [](double sigma, double T) {
    return (T > 0.0 && std::isfinite(T)) ? 2.0 * sigma * sigma / T : 0.0;
  };
  q.segment<3>(kVel).setConstant(p.vrw_m_s_sqrt_s * p.vrw_m_s_sqrt_s);
  q.segment<3>(kAtt).setConstant(p.arw_rad_sqrt_s * p.arw_rad_sqrt_s);
  q.segment<3>(kGyroBias).setConstant(gm(p.gyro_bias_instability_rad_s, p.gyro_bias_corr_time_s));
  q.segment<3>(kAccelBias).setConstant(gm(p.accel_bias_instability_m_s2, p.accel_bias_corr_time_s));
  q.segment<3>(kGyroScale).setConstant(gm(p.gyro_scale_std, p.scale_corr_time_s));
  q.segment<3>(kAccelScale).setConstant(gm(p.accel_scale_std, p.scale_corr_time_s));
  return q;
}

BlockMask blockMask(const ErrorCov& A) {
  BlockMask m{};
  for (int i = 0; i < kBlocks; ++i)
    for (int k = 0; k < kBlocks; ++k) m[i][k] = !A.block<3, 3>(3 * i, 3 * k).isZero(0.0);
  return m;
}

void multiplyBlockSparse(const ErrorCov& A, const BlockMask& mask, const ErrorCov& B,
                         ErrorCov* out) {
  out->setZero();
  for (int i = 0; i < kBlocks; ++i) {
    for (int k = 0; k < kBlocks; ++k) {
      if (!mask[i][k]) continue;
      out->block<3, kStateDim>(3 * i, 0).noalias() +=
          A.block<3, 3>(3 * i, 3 * k) * B.block<3, kStateDim>(3 * k, 0);
    }
  }
}

void discretize(const ErrorCov& F, const ErrorState& qc_diag, double dt_s, ErrorCov* Phi,
                ErrorCov* Qd) {
  // F is block sparse (14 of 49 blocks): products exploit it.
  const BlockMask mf = blockMask(F);
  ErrorCov F2;
  multiplyBlockSparse(F, mf, F, &F2);
  *Phi = F * dt_s + F2 * (0.5 * dt_s * dt_s);
  Phi->diagonal().array() += 1.0;
  // Second-order Van Loan: Qd = Qc dt + (F Qc + Qc F^T) dt^2 / 2 (Qc diagonal).
  const ErrorCov FQ = F * qc_diag.asDiagonal();
  *Qd = (FQ + FQ.transpose()) * (0.5 * dt_s * dt_s);
  Qd->diagonal() += qc_diag * dt_s;
}

void propagateCovariance(const ErrorCov& Phi, const ErrorCov& Qd, ErrorCov* P) {
  const BlockMask m = blockMask(Phi);
  ErrorCov PhiP, out;
  multiplyBlockSparse(Phi, m, *P, &PhiP);
  multiplyBlockSparse(Phi, m, PhiP.transpose(), &out);  // Phi (Phi P)^T = Phi P Phi^T
  *P = out + Qd;
}

Geodetic antennaPosition(const NavState& s, const Eigen::Vector3d& lever_arm_b_m) {
  return earth::offsetByNed(s.pos, s.q_nb * lever_arm_b_m);
}

Eigen::Matrix3d frameRotationPerPosition(const Geodetic& pos) {
  const earth::Radii r = earth::radiiOfCurvature(pos.lat_rad);
  const double rn = r.prime_vertical_m + pos.h_m, rm = r.meridian_m + pos.h_m;
  Eigen::Matrix3d T = Eigen::Matrix3d::Zero();
  T(0, 1) = 1.0 / rn;
  T(1, 0) = -1.0 / rm;
  T(2, 1) = -std::tan(pos.lat_rad) / rn;
  return T;
}

Eigen::Vector3d gnssPositionInnovation(const NavState& s, const Eigen::Vector3d& lever_arm_b_m,
                                       const Geodetic& gnss_pos) {
  // Difference of geodetic positions in metres at the GNSS point, plus the lever arm in n.
  return positionErrorNed(s.pos, gnss_pos) + s.q_nb * lever_arm_b_m;
}

Eigen::Matrix<double, 3, kStateDim> gnssPositionJacobian(const NavState& s,
                                                         const Eigen::Vector3d& lever_arm_b_m) {
  Eigen::Matrix<double, 3, kStateDim> H = Eigen::Matrix<double, 3, kStateDim>::Zero();
  const Eigen::Matrix3d L = skew(s.q_nb * lever_arm_b_m);
  H.block<3, 3>(0, kPos) = Eigen::Matrix3d::Identity() + L * frameRotationPerPosition(s.pos);
  H.block<3, 3>(0, kAtt) = L;
  return H;
}

Eigen::Vector3d antennaVelocity(const NavState& s, const Eigen::Vector3d& omega_ib_b,
                                const Eigen::Vector3d& lever_arm_b_m) {
  const Eigen::Vector3d w_in = earth::omega_ie_n(s.pos.lat_rad) + earth::omega_en_n(s.pos, s.v_n);
  return s.v_n + s.q_nb * omega_ib_b.cross(lever_arm_b_m) - w_in.cross(s.q_nb * lever_arm_b_m);
}

Eigen::Matrix<double, 3, kStateDim> gnssVelocityJacobian(const NavState& s,
                                                         const Eigen::Vector3d& omega_ib_b,
                                                         const Eigen::Vector3d& lever_arm_b_m) {
  Eigen::Matrix<double, 3, kStateDim> H = Eigen::Matrix<double, 3, kStateDim>::Zero();
  const Eigen::Matrix3d C_nb = s.q_nb.toRotationMatrix();
  const Eigen::Vector3d w_in = earth::omega_ie_n(s.pos.lat_rad) + earth::omega_en_n(s.pos, s.v_n);
  const Eigen::Matrix3d T = frameRotationPerPosition(s.pos);
  const Eigen::Matrix3d H_phi =
      skew(C_nb * omega_ib_b.cross(lever_arm_b_m)) - skew(w_in) * skew(C_nb * lever_arm_b_m);
  H.block<3, 3>(0, kPos) = skew(s.v_n) * T + H_phi * T;
  H.block<3, 3>(0, kVel).setIdentity();
  H.block<3, 3>(0, kAtt) = H_phi;
  H.block<3, 3>(0, kGyroBias) = -C_nb * skew(lever_arm_b_m);
  H.block<3, 3>(0, kGyroScale) = -C_nb * skew(lever_arm_b_m) * omega_ib_b.asDiagonal();
  return H;
}

NavState correctNavState(const NavState& c, const ErrorState& dx) {
  const Eigen::Vector3d dr = dx.segment<3>(kPos);
  const Eigen::Vector3d dtheta = frameRotationPerPosition(c.pos) * dr;
  NavState t = c;
  t.pos = earth::offsetByNed(c.pos, -dr);
  t.v_n = c.v_n - dx.segment<3>(kVel) + dtheta.cross(c.v_n);
  t.q_nb = (quatFromRotationVector(dx.segment<3>(kAtt) + dtheta) * c.q_nb).normalized();
  return t;
}

NavState perturbNavState(const NavState& t, const ErrorState& dx) {
  const Eigen::Vector3d dr = dx.segment<3>(kPos);
  const Eigen::Vector3d dtheta = frameRotationPerPosition(t.pos) * dr;
  NavState c = t;
  c.pos = earth::offsetByNed(t.pos, dr);
  c.v_n = t.v_n + dx.segment<3>(kVel) - dtheta.cross(t.v_n);
  c.q_nb = (quatFromRotationVector(-(dx.segment<3>(kAtt) + dtheta)) * t.q_nb).normalized();
  return c;
}

Eigen::Matrix<double, 9, 1> navErrorPsi(const NavState& c, const NavState& t) {
  Eigen::Matrix<double, 9, 1> e;
  const Eigen::Vector3d dr = positionErrorNed(c.pos, t.pos);
  const Eigen::Vector3d dtheta = frameRotationPerPosition(t.pos) * dr;
  const Eigen::Vector3d phi = rotationVectorFromQuat(t.q_nb * c.q_nb.conjugate());
  e << dr, c.v_n - t.v_n + dtheta.cross(t.v_n), phi - dtheta;
  return e;
}

Eigen::Matrix<double, 9, 9> psiToPhiJacobian(const NavState& s) {
  const Eigen::Matrix3d T = frameRotationPerPosition(s.pos);
  Eigen::Matrix<double, 9, 9> J = Eigen::Matrix<double, 9, 9>::Identity();
  J.block<3, 3>(3, 0) = skew(s.v_n) * T;
  J.block<3, 3>(6, 0) = T;
  return J;
}

}  // namespace graftnav
