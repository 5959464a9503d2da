#pragma once
// Slow bias wander of a residual against the lab's noise figures. Two independent realizations
// of a tested IMU's bias (the lab record grafted into the simulation, and the field) differ by a
// slow wander the lab's Allan fit predicts; within it, a residual's wander is noise, not missing
// physics (docs/mismatch-method.md, step 4 and gate b).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"

namespace graftnav {

// Allan figures of one sensor triad (calibration_result.h AllanTerms), SI: B in rad/s or m/s^2,
// K in rad/s/sqrt(s) or m/s^2/sqrt(s).
struct LabNoiseFigures {
  Eigen::Vector3d bias_instability = Eigen::Vector3d::Zero();
  Eigen::Vector3d rate_random_walk = Eigen::Vector3d::Zero();
};

// Expected standard deviation (about its record mean) of the difference of two independent bias
// realizations over a record of duration_s: sqrt(2 B^2 + K^2 T / 3) per axis (a random walk of
// intensity K has mean-removed variance K^2 T / 6 over [0, T]; two realizations double it).
Eigen::Vector3d expectedWanderSd(const LabNoiseFigures& lab, double duration_s);

// Ratio of the 99.9 % quantile to the expectation of that standard deviation for a random walk
// (Karhunen-Loeve eigenvalues 1 / (k pi)^2 of the mean-removed Brownian motion; 40000 draws:
// 50 % 0.84, 99 % 2.12, 99.9 % 2.63).
inline constexpr double kWanderSdQuantile999 = 2.63;

// Slow bias wander of one channel of the modelled residual (piecewise-linear bias at the
// bias_instability term's knots, fitted with a constant) against the lab's noise figures.
struct WanderCheck {
  int channel = 0;           // residual column, 0..5 (mismatchChannelNames)
  double fitted_sd = 0.0;    // SI, about the record mean
  double expected_sd = 0.0;  // expectedWanderSd plus the white noise the knots pass
  double limit = 0.0;        // kWanderSdQuantile999 x expected_sd
  bool within = false;       // within: noise, removed before listing unexplained spans
};

// Fits each channel's wander (a constant plus the hat functions of the bias_instability term of
// that channel's sensor, masked bins left out) to `residual` and compares its standard deviation
// with expectedWanderSd of the channel's lab figures (a sensor without figures gets no entry)
// plus the white noise the knots pass, bin_variance x columns / bins. `within_wander` (n x 6)
// holds the fitted wander of the channels found within, zero elsewhere.
std::vector<WanderCheck> checkWander(const Eigen::MatrixXd& residual,
                                     const std::vector<CandidateTerm>& terms,
                                     const std::optional<LabNoiseFigures>& gyro,
                                     const std::optional<LabNoiseFigures>& accel,
                                     const Eigen::Matrix<double, 6, 1>& bin_variance,
                                     const GridSpec& grid, const std::vector<char>& masked,
                                     Eigen::MatrixXd* within_wander);

}  // namespace graftnav
