#pragma once
// Drift of a static pose's mean against the other poses of one lab session. A pose mean's
// sigma-of-mean (per-sample std / sqrt(n)) holds white noise only; between poses minutes apart a
// MEMS bias moves by more (0.2 mg over a minute for a 1-mg, 1-h Gauss-Markov bias), and a fitting
// function that trusts the white sigmas reads that drift as curvature.
//
// Estimate from the static record's error rates (rad/s or m/s^2): window means over window_s, the
// structure function D = 1/2 mean_k (ybar_k - ybar_{k+m})^2 at a separation of
// m = round(separation_s / window_s) windows, less its white-noise part w (the within-window sample
// variance over the window's sample count); sigma = sqrt(max(0, D - w)) per axis.
//
// How well sigma^2 is known: a 600-s record holds only a few independent spans of 190 s, and the
// overlapping pairs share their increments. dof is Satterthwaite's 2 E[sigma^2]^2 / var(sigma^2),
// with var from the pair differences' covariance under a random-walk drift of the estimated size
// plus the white part: d_k = ybar_{k+m} - ybar_k has cov(d_k, d_l) = q max(0, m - |k - l|) +
// w (2 [k = l] - [|k - l| = m]), q = 2 sigma^2 / m, so var(D) = sum_kl cov^2 / (2 n^2) over the
// n = windows - m pairs. For 20 windows and m = 6 a pure random walk gives dof = 3.85 per axis.
// Infinity when sigma is 0 (nothing estimated is added).

#include <Eigen/Core>
#include <cmath>

#include "graftnav/nav/types.h"

namespace graftnav {

struct PoseDriftEstimate {
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();            // per axis, the unit of the rates
  Eigen::Vector3d dof = Eigen::Vector3d::Constant(INFINITY);  // of sigma^2, per axis
};

// Throws std::invalid_argument when window_s or separation_s is not positive, a sample has
// dt_s <= 0, or the record is shorter than window_s + separation_s (naming the lengths).
PoseDriftEstimate measurePoseDrift(const ImuSeries& static_error, bool gyro, double window_s,
                                   double separation_s);

// One drift for all three axes of a sensor (they share its technology): sigma^2 the mean of the
// axes' sigma^2, dof by Satterthwaite over the axes (three times an axis's for equal axes).
PoseDriftEstimate pooledOverAxes(const PoseDriftEstimate& per_axis);

}  // namespace graftnav
