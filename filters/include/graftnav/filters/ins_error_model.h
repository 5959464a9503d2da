#pragma once
// The 21-state INS error model of the reference EKF (seed Eq. 22, psi-angle form, NED).
//
// Error state x (computed minus true, except the sensor states which are true minus estimated,
// i.e. the error left in the corrected sensor output):
//   [0,3)   dr    position error, NED metres, resolved in the computed frame c
//   [3,6)   dv    velocity error (m/s), c frame: dv = v_c - C_cn v_true
//   [6,9)   psi   psi-angle attitude error: C_nb_computed = (I - [psi x]) C_cb_true
//   [9,12)  dbg   gyro bias (rad/s)            } first-order Gauss-Markov,
//   [12,15) dba   accel bias (m/s^2)           } parameters from ImuProfile
//   [15,18) dsg   gyro scale factor (fraction) }
//   [18,21) dsa   accel scale factor (fraction)}
// Sensor model: omega_meas = (I + diag(s_g)) omega + b_g + w_g, f likewise; the filter corrects
// raw increments as (raw - b dt) / (1 + s), so the residual output error is db + diag(omega) ds.
//
// Continuous dynamics dx/dt = F x + G w (docs/ekf.md derives each block):
//   d(dr)/dt  = -[w_en x] dr + dv
//   d(dv)/dt  = dg(dr) - [(2 w_ie + w_en) x] dv + [f_n x] psi + C_nb (dba + diag(f_b) dsa)
//   d(psi)/dt = -[(w_ie + w_en) x] psi - C_nb (dbg + diag(w_ib_b) dsg)
//   d(b)/dt   = -b / T + w_b,  d(s)/dt = -s / T + w_s
// with the psi-model gravity error dg = (g/R) diag(-1, -1, 2) dr (Schuler terms, vertical
// instability), R = sqrt(R_M R_N) + h.
// Noise (seed Eq. 26): ARW^2 on psi, VRW^2 on dv, 2 sigma^2 / T on each Gauss-Markov state.

#include <Eigen/Core>
#include <array>

#include "graftnav/estimation/imu_error_estimate.h"
#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/types.h"

namespace graftnav {

namespace ekf {
constexpr int kStateDim = 21;
constexpr int kPos = 0;
constexpr int kVel = 3;
constexpr int kAtt = 6;
constexpr int kGyroBias = 9;
constexpr int kAccelBias = 12;
constexpr int kGyroScale = 15;
constexpr int kAccelScale = 18;
}  // namespace ekf

using ErrorState = Eigen::Matrix<double, ekf::kStateDim, 1>;
using ErrorCov = Eigen::Matrix<double, ekf::kStateDim, ekf::kStateDim>;

// Raw increments corrected by the estimates: (raw - b dt) / (1 + s).
ImuSample correctImuSample(const ImuSample& raw, const ImuErrorEstimate& e);

// The dynamics matrix at the computed state with the (corrected) body rate and specific force.
ErrorCov errorDynamics(const NavState& s, const Eigen::Vector3d& omega_ib_b,
                       const Eigen::Vector3d& f_b, const ImuProfile& profile);

// Continuous noise spectral density in state coordinates (diagonal, seed Eq. 26). The white
// noise of the sensors enters through C_nb; with equal per-axis densities C Q C^T = Q.
ErrorState continuousNoiseDensity(const ImuProfile& profile);

// Transition and discrete noise over dt from F (held constant): Phi = I + F dt + (F dt)^2 / 2,
// Qd = Qc dt + (F Qc + Qc F^T) dt^2 / 2 (Van Loan's integral to second order, Qc diagonal).
void discretize(const ErrorCov& F, const ErrorState& qc_diag, double dt_s, ErrorCov* Phi,
                ErrorCov* Qd);

// P <- Phi P Phi^T + Qd using the 3x3 block sparsity of Phi (about 2.5x fewer flops than dense).
void propagateCovariance(const ErrorCov& Phi, const ErrorCov& Qd, ErrorCov* P);

// Block-sparse helpers on the 7 x 7 grid of 3 x 3 blocks.
constexpr int kBlocks = ekf::kStateDim / 3;
using BlockMask = std::array<std::array<bool, kBlocks>, kBlocks>;
BlockMask blockMask(const ErrorCov& A);
// out = A B, skipping the zero blocks of A named by mask.
void multiplyBlockSparse(const ErrorCov& A, const BlockMask& mask, const ErrorCov& B,
                         ErrorCov* out);

// Position at the GNSS antenna: pos + C_nb lever_arm_b as a geodetic position.
Geodetic antennaPosition(const NavState& s, const Eigen::Vector3d& lever_arm_b_m);
// Innovation of a GNSS position fix: (antenna position computed by the INS) - (GNSS), NED metres
// at the INS position, and its Jacobian wrt the error state: [I, 0, [(C_nb l) x], 0...].
Eigen::Vector3d gnssPositionInnovation(const NavState& s, const Eigen::Vector3d& lever_arm_b_m,
                                       const Geodetic& gnss_pos);
Eigen::Matrix<double, 3, ekf::kStateDim> gnssPositionJacobian(const NavState& s,
                                                              const Eigen::Vector3d& lever_arm_b_m);
// GNSS velocity at the antenna: v_n + C_nb (omega_ib_b x l) - omega_in_n x (C_nb l), and the
// Jacobian of (INS - GNSS) wrt the error state (dv, psi, dbg, dsg blocks).
Eigen::Vector3d antennaVelocity(const NavState& s, const Eigen::Vector3d& omega_ib_b,
                                const Eigen::Vector3d& lever_arm_b_m);
Eigen::Matrix<double, 3, ekf::kStateDim> gnssVelocityJacobian(const NavState& s,
                                                              const Eigen::Vector3d& omega_ib_b,
                                                              const Eigen::Vector3d& lever_arm_b_m);

// d(theta) of the n frame for a position error dr (rad): the rotation between the true and the
// computed local-level frames, dtheta = T dr, T = [[0, 1/(R_N+h), 0], [-1/(R_M+h), 0, 0],
// [0, -tan(lat)/(R_N+h), 0]].
Eigen::Matrix3d frameRotationPerPosition(const Geodetic& pos);

// Applies an estimated PVA error to a computed state (closed-loop reset):
// position -= dr; v_true = v_c - dv + dtheta x v_c; C_true = (I + [(psi + dtheta) x]) C_c,
// dtheta = T dr (first order in the error).
NavState correctNavState(const NavState& computed, const ErrorState& dx);
// The inverse: the computed state obtained from the true one with PVA error dx (tests, RTS).
NavState perturbNavState(const NavState& truth, const ErrorState& dx);
// The PVA error (dr, dv, psi) of `computed` relative to `truth` in this model's convention.
Eigen::Matrix<double, 9, 1> navErrorPsi(const NavState& computed, const NavState& truth);

// 9x9 map from the PVA error (dr, dv, psi) to the error in the true n frame
// (dr, v_c - v_true, phi) with phi = psi + dtheta: used to report PvaSigma.
Eigen::Matrix<double, 9, 9> psiToPhiJacobian(const NavState& s);

}  // namespace graftnav
