#pragma once
// Gyro calibration from lab data (seed Eq. 9-11) and one least-squares problem over all rates.
//
// Rate-table runs: lab/rate/<x|y|z>_<pos|neg>_<deg/s>.txt, the named body axis pointing up and
// turning at constant rate (pos = right-handed positive), whole turns. Over n whole turns of
// duration T the true mean body rate is
//   omega_true = e_axis * (sign * 2 pi n / T + w_e sin(lat))
// (the up-pointing axis also senses the vertical Earth rate; the horizontal Earth rate rotates
// in the body and averages to zero over whole turns). The measured mean rate is the integrated
// angle over T, so runs of varying rate (hand rotations) work too: only the total angle matters.
//
// Estimators:
//  - gyroBiasFromUpDown: Eq. 9, b_i = (l_i,up + l_i,down) / 2 with l = omega_mean - omega_ie_b
//    (the Earth rate at the known pose attitude and lab latitude is removed first).
//  - gyroScaleFromTurns: Eq. 10-11 generalized with the bias and Earth rate removed:
//    column i of M = [(L_pos - b T_pos) - (L_neg - b T_neg)] / (theta_pos - theta_neg), with
//    theta the true angle about axis i; averaged over the rates that have both directions.
//  - calibrateGyroLeastSquares: [M | b] from the static poses (true = omega_ie_b) and every rate
//    run (true = omega_true above) in one weighted least squares (fitLinearSensorModel, Ceres,
//    covariance scaled as described in six_position.h). The sigma of a run's mean rate is the
//    static per-sample gyro noise / sqrt(samples): hand-motion ripple does not enter the integral.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graftnav/calibration/six_position.h"
#include "graftnav/calibration/theoretical_output.h"

namespace graftnav {

struct RateRun {
  std::string file;                 // for messages
  int axis = 0;                     // 0 x, 1 y, 2 z
  int sign = 1;                     // +1 pos, -1 neg
  double nominal_rate_rad_s = 0.0;  // from the file name, > 0
  int turns = 0;                    // whole turns (from wholeTurns)
  SegmentStats stats;
  // True angle about `axis` over the run and true mean rate vector (see the header comment).
  double trueAngle_rad(double lat_rad) const;
  Eigen::Vector3d trueMeanRate_b(double lat_rad) const;
};

// A run from its statistics and the parsed file name (axis, sign, nominal rate in deg/s > 0);
// turns are left 0 (see assignWholeTurns). Throws std::invalid_argument naming `file`.
RateRun makeRateRun(const std::string& file, int axis, int sign, double rate_deg_s,
                    const SegmentStats& stats);

struct RateRunOptions {
  // |rate * T / 360 - round| above this (in turns) rejects the run as "not whole turns".
  double max_turn_fraction = 0.15;
  // The measured |angle| / (2 pi n) must be within this relative distance of 1.
  double max_angle_mismatch = 0.3;
};

// Sets run.turns from the nominal rate and duration, and checks it against the integrated angle
// about the axis. Throws std::runtime_error naming the file when the run is not whole turns.
void assignWholeTurns(RateRun& run, const RateRunOptions& options = {});

struct GyroBiasEstimate {
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_sigma = Eigen::Vector3d::Zero();
};

// Eq. 9. `poses` must contain x_up .. z_down (by name); throws std::invalid_argument naming the
// missing pose.
GyroBiasEstimate gyroBiasFromUpDown(const std::vector<StaticPose>& poses, double lat_rad);

struct TurnTableEstimate {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d M_sigma = Eigen::Matrix3d::Zero();  // from the gyro white noise only
  int pairs_used = 0;
};

// Eq. 10-11. Needs a pos and a neg run of the same nominal rate for every axis; throws
// std::invalid_argument naming the axis otherwise. rate_noise_std: per-sample gyro noise (rad/s).
TurnTableEstimate gyroScaleFromTurns(const std::vector<RateRun>& runs, const Eigen::Vector3d& bias,
                                     double lat_rad, const Eigen::Vector3d& rate_noise_std);

// The observations of the joint least squares (static poses + rate runs); exposed for the
// fitting functions and reports.
std::vector<LinearObservation> gyroObservations(const std::vector<StaticPose>& poses,
                                                const std::vector<RateRun>& runs, double lat_rad,
                                                const Eigen::Vector3d& rate_noise_std);

LinearModelFit calibrateGyroLeastSquares(const std::vector<StaticPose>& poses,
                                         const std::vector<RateRun>& runs, double lat_rad,
                                         const LinearModelOptions& options = {});

// Mean per-sample gyro noise std over static poses (rad/s); throws when `poses` is empty.
Eigen::Vector3d staticGyroNoiseStd(const std::vector<StaticPose>& poses);

}  // namespace graftnav
