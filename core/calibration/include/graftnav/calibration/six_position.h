#pragma once
// Linear sensor model fit and the six-position accelerometer calibration (seed Eq. 3-8).
//
// Model (Eq. 3): measured = M * true + bias, M = I + S + N (3x3), i.e. the 3x4 matrix [M | bias].
// Given K >= 4 observations (true_k, measured_k) with per-axis 1-sigma of the measured mean, the
// 12 parameters are solved as a weighted least-squares problem in Ceres (residual
// (measured - M true - bias) / sigma, one 3-residual block per observation) and their 12x12
// covariance is computed with ceres::Covariance. Because the weights come from the sample
// scatter of each segment (white noise, std/sqrt(n)) and ignore model errors (pose misalignment,
// correlated noise), the covariance is multiplied by the reduced chi-square
// s^2 = 2 cost / (3K - 12) when that exceeds 1 (CovarianceScaling::kReducedChiSquareAtLeastOne,
// the default); with 3K == 12 no scaling is possible and the noise-propagated covariance is kept.
//
// Six-position poses: x_up means the x axis points up (the x accelerometer reads +g). Default
// attitudes (yaw 0, ZYX Euler [roll, pitch, yaw]): x_up [0, +90, 0], x_down [0, -90, 0],
// y_up [-90, 0, 0], y_down [+90, 0, 0], z_up [180, 0, 0], z_down [0, 0, 0].

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "graftnav/calibration/calibration_result.h"
#include "graftnav/calibration/theoretical_output.h"

namespace graftnav {

enum class CovarianceScaling { kNone, kReducedChiSquare, kReducedChiSquareAtLeastOne };

struct LinearObservation {
  std::string name;
  Eigen::Vector3d true_value = Eigen::Vector3d::Zero();
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma = Eigen::Vector3d::Ones();  // 1-sigma of `measured`, >= 0 (0 is floored)
};

struct LinearModelOptions {
  CovarianceScaling scaling = CovarianceScaling::kReducedChiSquareAtLeastOne;
  // Floor for each sigma, relative to the largest |measured| component (guards zero-noise data).
  double relative_sigma_floor = 1e-9;
};

struct LinearModelFit {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  // Own-axis powers fitted with M (fitLinearSensorModel's axis_degree): row i holds the
  // coefficients of true_i^2, true_i^3, true_i^4 (zero beyond axis_degree[i]).
  std::array<int, 3> axis_degree = {1, 1, 1};
  Eigen::Matrix3d axis_powers = Eigen::Matrix3d::Zero();
  // Covariance of [M row-major (9), bias (3)], after scaling.
  Eigen::Matrix<double, 12, 12> covariance = Eigen::Matrix<double, 12, 12>::Zero();
  Eigen::Matrix3d M_sigma = Eigen::Matrix3d::Zero();
  Eigen::Vector3d bias_sigma = Eigen::Vector3d::Zero();
  double chi2 = 0.0;                       // sum of squared whitened residuals
  int dof = 0;                             // 3K - 12 - (number of own-axis powers)
  double covariance_scale = 1.0;           // factor applied to the covariance
  double residual_rms = 0.0;               // RMS of the unwhitened residuals (units of `measured`)
  std::vector<Eigen::Vector3d> residuals;  // measured - (M true + bias + powers), per observation
};

// Throws std::invalid_argument when fewer than 4 observations are given, a value is not finite or
// a sigma < 0 (0 is floored, see LinearModelOptions), or an axis degree is outside 1..4, and
// std::runtime_error when the true values do not span 3-D (+ constant), i.e. the covariance is
// rank deficient (names the observations).
// axis_degree: with axis_degree[i] = d > 1, measured_i also carries a_i2 true_i^2 + ... +
// a_id true_i^d, fitted together with M and bias. A sensor whose fitting function (Eq. 21) bends
// does not fit the linear model: on random_14_15 an accelerometer quadratic of 1.4e-3 per m/s^2
// left a reduced chi-square of 1.6e5, which scaled M_sigma to 5e-3 (the lab measures M to
// ~1e-4), so the mismatch finder's lab gates took a 0.24-deg mounting rotation and 0.3-0.7 %
// scale asymmetries for calibration error. The covariance is that of M and bias with the powers
// fitted alongside (they are not reported: the fitting functions carry the curvature).
LinearModelFit fitLinearSensorModel(const std::vector<LinearObservation>& obs,
                                    const LinearModelOptions& options = {},
                                    const std::array<int, 3>& axis_degree = {1, 1, 1});

// Closed form of Eq. 8: [M | b] = U A^T (A A^T)^-1 with A = [true; 1] (4 x K), U measured (3 x K).
Eigen::Matrix<double, 3, 4> closedFormLinearModel(
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& U,
    const Eigen::Matrix<double, 4, Eigen::Dynamic>& A);

// Default attitude (rad, [roll, pitch, yaw]) of a six-position pose named x_up .. z_down;
// throws std::invalid_argument for another name.
Eigen::Vector3d sixPositionDefaultEuler(const std::string& pose_name);

// A static lab pose: its recording statistics and the attitude it was held at.
struct StaticPose {
  std::string name;  // e.g. "x_up" or a tilt name
  std::string file;  // for error messages
  Eigen::Matrix3d C_nb = Eigen::Matrix3d::Identity();
  SegmentStats stats;
};

// Six-position (or more: tilts too) accelerometer calibration: the observations are the pose
// means with f_true = staticSpecificForce_b(C_nb, g) and the sigma-of-mean of each pose.
LinearModelFit calibrateAccelStaticPoses(const std::vector<StaticPose>& poses, double gravity_m_s2,
                                         const LinearModelOptions& options = {});

// Copies M, bias and their sigmas into a SensorCalibration.
void storeLinearFit(const LinearModelFit& fit, const std::string& method, SensorCalibration& out);

}  // namespace graftnav
