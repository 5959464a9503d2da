#pragma once
// Drift of a static pose's mean against the other poses of one lab session. A pose mean's
// sigma-of-mean (per-sample std / sqrt(n)) holds white noise only; between poses minutes apart a
// MEMS bias moves by more (0.2 mg over a minute for a 1-mg, 1-h Gauss-Markov bias), and a fitting
// function that trusts the white sigmas reads that drift as curvature.
//
// Estimate from the static record's error rates (rad/s or m/s^2): window means over window_s, the
// structure function D = 1/2 mean_k (ybar_k - ybar_{k+m})^2 at a separation of
// m = round(separation_s / window_s) windows, less its white-noise part (the within-window sample
// variance over the window's sample count); sigma = sqrt(max(0, D - white)) per axis.

#include <Eigen/Core>

#include "graftnav/core/types.h"

namespace graftnav {

// Throws std::invalid_argument when window_s or separation_s is not positive, a sample has
// dt_s <= 0, or the record is shorter than window_s + separation_s (naming the lengths).
Eigen::Vector3d poseDriftSigma(const ImuSeries& static_error, bool gyro, double window_s,
                               double separation_s);

}  // namespace graftnav
