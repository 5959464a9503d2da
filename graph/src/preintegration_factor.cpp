#include "graftnav/graph/preintegration_factor.h"

#include "graftnav/nav/rotation.h"
#include "graftnav/graph/right_quaternion_manifold.h"

namespace graftnav {
namespace {
using Mat93 = Eigen::Matrix<double, 9, 3>;
using Mat93R = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
using Mat94R = Eigen::Matrix<double, 9, 4, Eigen::RowMajor>;
constexpr int kP = ImuPreintegration::kP;
constexpr int kV = ImuPreintegration::kV;
constexpr int kR = ImuPreintegration::kR;
}  // namespace

PreintegrationFactor::PreintegrationFactor(const ImuPreintegration* pre,
                                           const Eigen::Vector3d& omega_ie_w,
                                           const LinearGravity& gravity)
    : pre_(pre),
      with_scale_(pre->withScale()),
      omega_ie_w_(omega_ie_w),
      gravity_(gravity),
      sqrt_info_(pre->sqrtInformation()) {
  set_num_residuals(9);
  *mutable_parameter_block_sizes() = {3, 4, 3, 3, 3, 3, 4, 3};
  if (with_scale_) {
    mutable_parameter_block_sizes()->push_back(3);
    mutable_parameter_block_sizes()->push_back(3);
  }
}

void PreintegrationFactor::corrected(const Eigen::Vector3d& bg, const Eigen::Vector3d& ba,
                                     const double* sg, const double* sa, Eigen::Vector3d* phi_b,
                                     Eigen::Vector3d* dv_hat, Eigen::Vector3d* dp_hat) const {
  const ImuPreintegration& pre = *pre_;
  if (!with_scale_) {
    *phi_b = pre.dR_dbg() * (bg - pre.bgLin());
    *dv_hat = pre.correctedDeltaV(bg, ba);
    *dp_hat = pre.correctedDeltaP(bg, ba);
    return;
  }
  ImuScaleFactors s;
  s.gyro = Eigen::Map<const Eigen::Vector3d>(sg);
  s.accel = Eigen::Map<const Eigen::Vector3d>(sa);
  *phi_b = pre.rotationCorrection(bg, s);
  *dv_hat = pre.correctedDeltaV(bg, ba, s);
  *dp_hat = pre.correctedDeltaP(bg, ba, s);
}

bool PreintegrationFactor::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> p_i(parameters[0]);
  const Eigen::Map<const Eigen::Quaterniond> q_i(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> v_i(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> bg_i(parameters[3]);
  const Eigen::Map<const Eigen::Vector3d> ba_i(parameters[4]);
  const Eigen::Map<const Eigen::Vector3d> p_j(parameters[5]);
  const Eigen::Map<const Eigen::Quaterniond> q_j(parameters[6]);
  const Eigen::Map<const Eigen::Vector3d> v_j(parameters[7]);

  const ImuPreintegration& pre = *pre_;
  const double T = pre.dt_s();
  const Eigen::Matrix3d R_i = q_i.toRotationMatrix();
  const Eigen::Matrix3d R_iT = R_i.transpose();
  const Eigen::Matrix3d R_j = q_j.toRotationMatrix();
  const Eigen::Vector3d& w = omega_ie_w_;
  const Eigen::Matrix3d W = skew(w);
  // Gravity for velocity at the mid-point, for position at the 1/3 point (exact for gravity
  // varying linearly along the interval: int_0^T int_0^s g = g(t = T/3) T^2/2).
  const Eigen::Vector3d g = gravity_.at(0.5 * (p_i + p_j));
  const Eigen::Vector3d g_p = gravity_.at((2.0 * p_i + p_j) / 3.0);
  const Eigen::Matrix3d& G = gravity_.G_w;

  Eigen::Vector3d phi_b, dv_hat, dp_hat;
  corrected(bg_i, ba_i, with_scale_ ? parameters[8] : nullptr,
            with_scale_ ? parameters[9] : nullptr, &phi_b, &dv_hat, &dp_hat);
  const Eigen::Matrix3d dR_hat = pre.deltaR() * dcmFromRotationVector(phi_b);
  const Eigen::Vector3d c = pre.coriolisMoment();
  const Eigen::Vector3d m1 = pre.firstMoment();

  const Eigen::Vector3d dp =
      p_j - p_i - v_i * T - 0.5 * g_p * T * T + W * (2.0 * v_i + v_j) * (T * T / 3.0);
  const Eigen::Vector3d dv = v_j - v_i - g * T + 2.0 * W * (p_j - p_i);
  const Eigen::Vector3d A = R_iT * w;
  const Eigen::Matrix3d E = dcmFromRotationVector(w * T);
  const Eigen::Matrix3d M = dR_hat.transpose() * R_iT * E * R_j;
  const Eigen::Vector3d r_phi = rotationVectorFromQuat(Eigen::Quaterniond(M));

  Eigen::Matrix<double, 9, 1> r;
  r.segment<3>(kP) = R_iT * dp + A.cross(c) - dp_hat;
  r.segment<3>(kV) = R_iT * dv + A.cross(m1) - dv_hat;
  r.segment<3>(kR) = r_phi;
  Eigen::Map<Eigen::Matrix<double, 9, 1>>{residuals} = sqrt_info_ * r;

  if (jacobians == nullptr) return true;
  const Eigen::Matrix3d Jr_inv = rightJacobianInverseSO3(r_phi);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();

  if (jacobians[0]) {  // p_i
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = -R_iT * (I + (T * T / 3.0) * G);
    J.block<3, 3>(kV, 0) = R_iT * (-0.5 * T * G - 2.0 * W);
    Eigen::Map<Mat93R>{jacobians[0]} = sqrt_info_.lazyProduct(J);
  }
  if (jacobians[1]) {  // q_i (tangent, then ambient)
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = skew(R_iT * dp) - skew(c) * skew(A);
    J.block<3, 3>(kV, 0) = skew(R_iT * dv) - skew(m1) * skew(A);
    J.block<3, 3>(kR, 0) = -Jr_inv * R_j.transpose() * E.transpose() * R_i;
    Eigen::Map<Mat94R>{jacobians[1]} = sqrt_info_.lazyProduct(J * tangentToAmbientJacobian(q_i));
  }
  if (jacobians[2]) {  // v_i
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = R_iT * (-T * I + (2.0 * T * T / 3.0) * W);
    J.block<3, 3>(kV, 0) = -R_iT;
    Eigen::Map<Mat93R>{jacobians[2]} = sqrt_info_.lazyProduct(J);
  }
  if (jacobians[3]) {  // bg_i
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = -pre.dp_dbg();
    J.block<3, 3>(kV, 0) = -pre.dv_dbg();
    J.block<3, 3>(kR, 0) = -Jr_inv * M.transpose() * rightJacobianSO3(phi_b) * pre.dR_dbg();
    Eigen::Map<Mat93R>{jacobians[3]} = sqrt_info_.lazyProduct(J);
  }
  if (jacobians[4]) {  // ba_i
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = -pre.dp_dba();
    J.block<3, 3>(kV, 0) = -pre.dv_dba();
    Eigen::Map<Mat93R>{jacobians[4]} = sqrt_info_.lazyProduct(J);
  }
  if (jacobians[5]) {  // p_j
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = R_iT * (I - (T * T / 6.0) * G);
    J.block<3, 3>(kV, 0) = R_iT * (-0.5 * T * G + 2.0 * W);
    Eigen::Map<Mat93R>{jacobians[5]} = sqrt_info_.lazyProduct(J);
  }
  if (jacobians[6]) {  // q_j
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kR, 0) = Jr_inv;
    Eigen::Map<Mat94R>{jacobians[6]} = sqrt_info_.lazyProduct(J * tangentToAmbientJacobian(q_j));
  }
  if (jacobians[7]) {  // v_j
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = R_iT * W * (T * T / 3.0);
    J.block<3, 3>(kV, 0) = R_iT;
    Eigen::Map<Mat93R>{jacobians[7]} = sqrt_info_.lazyProduct(J);
  }
  if (!with_scale_) return true;
  if (jacobians[8]) {  // sg_i
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = -pre.dp_dsg();
    J.block<3, 3>(kV, 0) = -pre.dv_dsg();
    J.block<3, 3>(kR, 0) = -Jr_inv * M.transpose() * rightJacobianSO3(phi_b) * pre.dR_dsg();
    Eigen::Map<Mat93R>{jacobians[8]} = sqrt_info_.lazyProduct(J);
  }
  if (jacobians[9]) {  // sa_i
    Mat93 J = Mat93::Zero();
    J.block<3, 3>(kP, 0) = -pre.dp_dsa();
    J.block<3, 3>(kV, 0) = -pre.dv_dsa();
    Eigen::Map<Mat93R>{jacobians[9]} = sqrt_info_.lazyProduct(J);
  }
  return true;
}

void PreintegrationFactor::predict(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
                                   const Eigen::Vector3d& v_i, const Eigen::Vector3d& bg_i,
                                   const Eigen::Vector3d& ba_i, Eigen::Vector3d* p_j,
                                   Eigen::Quaterniond* q_j, Eigen::Vector3d* v_j) const {
  predict(p_i, q_i, v_i, bg_i, ba_i, pre_->scaleLin(), p_j, q_j, v_j);
}

void PreintegrationFactor::predict(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
                                   const Eigen::Vector3d& v_i, const Eigen::Vector3d& bg_i,
                                   const Eigen::Vector3d& ba_i, const ImuScaleFactors& s_i,
                                   Eigen::Vector3d* p_j, Eigen::Quaterniond* q_j,
                                   Eigen::Vector3d* v_j) const {
  const ImuPreintegration& pre = *pre_;
  const double T = pre.dt_s();
  const Eigen::Matrix3d R_i = q_i.toRotationMatrix();
  const Eigen::Vector3d& w = omega_ie_w_;
  const Eigen::Matrix3d W = skew(w);
  const Eigen::Vector3d A = R_i.transpose() * w;
  Eigen::Vector3d phi_b, dv_hat, dp_hat;
  corrected(bg_i, ba_i, s_i.gyro.data(), s_i.accel.data(), &phi_b, &dv_hat, &dp_hat);
  // Solve r_p = r_v = 0 for (p_j, v_j) by fixed-point iteration (the Coriolis and gravity
  // couplings are small), and r_phi = 0 for q_j exactly.
  Eigen::Vector3d pj = p_i + v_i * T, vj = v_i;
  for (int it = 0; it < 3; ++it) {
    const Eigen::Vector3d g = gravity_.at(0.5 * (p_i + pj));
    const Eigen::Vector3d g_p = gravity_.at((2.0 * p_i + pj) / 3.0);
    vj = v_i + g * T - 2.0 * W * (pj - p_i) + R_i * (dv_hat - A.cross(pre.firstMoment()));
    pj = p_i + v_i * T + 0.5 * g_p * T * T - W * (2.0 * v_i + vj) * (T * T / 3.0) +
         R_i * (dp_hat - A.cross(pre.coriolisMoment()));
  }
  *p_j = pj;
  *v_j = vj;
  const Eigen::Matrix3d R_j =
      dcmFromRotationVector(-w * T) * R_i * (pre.deltaR() * dcmFromRotationVector(phi_b));
  *q_j = Eigen::Quaterniond(R_j).normalized();
}

}  // namespace graftnav
