#pragma once
// Typed result of the lab calibration (what `graftnav calibrate` writes to calibration.yaml and the
// grafting step reads back). SI units throughout.
//
// Sensor model (seed Eq. 1-3): measured = M * true + bias + noise, with M = I + S + N
// (S diagonal scale-factor errors, N off-diagonal non-orthogonalities). M and bias come with
// 1-sigma uncertainties. Accelerometer quantities in m/s^2, gyro in rad/s.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace graftnav {

// Per-axis real-time fitting function (seed Eq. 21): measured = sum_k coeffs[k] * true^k
// (coefficients lowest order first), degree chosen by k-fold cross-validation.
struct PolynomialFit {
  int degree = 1;
  std::vector<double> coeffs;        // size degree + 1, lowest order first
  std::vector<double> coeffs_sigma;  // 1-sigma of each coefficient
  double cv_rms = 0.0;               // cross-validated RMS prediction error (NaN: not validated)
  double residual_rms = 0.0;         // RMS residual of the final fit on all points
  int n_points = 0;
  // The degree-2 coefficient the degree test weighed, c2 of the fixed degree-2 fit, and its
  // 1-sigma, also when the test kept a line (NaN: the points support no quadratic). A line
  // means the curvature was not significant at degree_alpha, not that it is zero; the mismatch
  // finder weighs this estimate when the field cannot tell a gain from a curvature
  // (mismatch/gain_or_curvature.h).
  double c2_tested = std::nan("");
  double c2_tested_sigma = std::nan("");
  // How this fit moves under an input-output shape it leaves out, per unit of that shape's
  // coefficient, from the same points and weights (least squares is linear in y): an asymmetric
  // gain d |x| moves the slope c1 by d * slope_per_abs and the degree-2 estimate c2_tested by
  // d * c2_tested_per_abs (poses at -g, 0, +g: slope 0; a tilted pose, which supports the
  // quadratic, gives c2_tested_per_abs near 1 / g); a curvature k2 x^2 moves the
  // slope by k2 * slope_per_sq (0 when the fit has an x^2 term). NaN: not computed (a fit of
  // degree 3 or more, or no quadratic supported for c2_tested_per_abs). The mismatch finder uses
  // them to weigh a field gain on a one-signed axis against an asymmetry the lab folded into its
  // quadratic (mismatch/gain_or_curvature.h).
  double slope_per_abs = std::nan("");
  double slope_per_sq = std::nan("");
  double c2_tested_per_abs = std::nan("");
  double evaluate(double x) const {
    double y = 0.0, p = 1.0;
    for (double c : coeffs) {
      y += c * p;
      p *= x;
    }
    return y;
  }
};

// Allan-variance noise terms fitted on the standard model
//   AVAR(tau) = N^2/tau + (2 ln2/pi) B^2 + K^2 tau / 3
// (N white noise: ARW rad/sqrt(s) or VRW m/s/sqrt(s); B bias instability rad/s or m/s^2;
//  K rate random walk rad/s/sqrt(s) or m/s^2/sqrt(s)).
struct AllanTerms {
  Eigen::Vector3d white_noise = Eigen::Vector3d::Zero();
  Eigen::Vector3d white_noise_sigma = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_instability = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_instability_sigma = Eigen::Vector3d::Zero();
  Eigen::Vector3d rate_random_walk = Eigen::Vector3d::Zero();
  Eigen::Vector3d rate_random_walk_sigma = Eigen::Vector3d::Zero();
};

struct SensorCalibration {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  Eigen::Matrix3d M_sigma = Eigen::Matrix3d::Zero();
  Eigen::Vector3d bias_sigma = Eigen::Vector3d::Zero();
  std::string method;  // e.g. "six_position_ceres", "rate_table_ceres", "multi_position"
  bool has_allan = false;
  AllanTerms allan;
  bool has_fit = false;
  std::array<PolynomialFit, 3> fit;
  // Inverse model: true = M^-1 (measured - bias).
  Eigen::Vector3d correct(const Eigen::Vector3d& measured) const {
    return M.inverse() * (measured - bias);
  }
};

struct CalibrationResult {
  std::string case_name;
  double lab_latitude_deg = 0.0;
  double gravity_m_s2 = 0.0;  // gravity magnitude used for the theoretical output
  SensorCalibration accel;
  SensorCalibration gyro;
};

}  // namespace graftnav
