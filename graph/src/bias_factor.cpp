#include "graftnav/graph/bias_factor.h"

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>

namespace graftnav {

void BiasProcess::discretize(double T_s, double* phi, double* sigma_d) const {
  if (!(sigma > 0.0) || !(T_s > 0.0)) {
    throw std::invalid_argument("BiasProcess::discretize: sigma=" + std::to_string(sigma) +
                                " and T=" + std::to_string(T_s) + " must be positive");
  }
  if (tau_s > 0.0 && std::isfinite(tau_s)) {
    *phi = std::exp(-T_s / tau_s);
    *sigma_d = sigma * std::sqrt(-std::expm1(-2.0 * T_s / tau_s));
  } else {
    *phi = 1.0;
    *sigma_d = sigma * std::sqrt(T_s);
  }
}

BiasFactor::BiasFactor(const BiasProcess& gyro, const BiasProcess& accel, double dt_s) {
  double sg = 0.0, sa = 0.0;
  gyro.discretize(dt_s, &phi_g_, &sg);
  accel.discretize(dt_s, &phi_a_, &sa);
  inv_sigma_g_ = 1.0 / sg;
  inv_sigma_a_ = 1.0 / sa;
}

bool BiasFactor::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> bg_i(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> ba_i(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> bg_j(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> ba_j(parameters[3]);
  Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
  r.head<3>() = (bg_j - phi_g_ * bg_i) * inv_sigma_g_;
  r.tail<3>() = (ba_j - phi_a_ * ba_i) * inv_sigma_a_;
  if (jacobians == nullptr) return true;
  using Mat63R = Eigen::Matrix<double, 6, 3, Eigen::RowMajor>;
  const double scale[4] = {-phi_g_ * inv_sigma_g_, -phi_a_ * inv_sigma_a_, inv_sigma_g_,
                           inv_sigma_a_};
  for (int b = 0; b < 4; ++b) {
    if (!jacobians[b]) continue;
    Eigen::Map<Mat63R> J(jacobians[b]);
    J.setZero();
    const int row = (b % 2 == 0) ? 0 : 3;
    J.block<3, 3>(row, 0) = scale[b] * Eigen::Matrix3d::Identity();
  }
  return true;
}

}  // namespace graftnav
