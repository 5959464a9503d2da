#pragma once
// Rauch-Tung-Striebel smoother over the recorded forward pass of the closed-loop EKF.
//
// Records are kept at every GNSS update and every record_interval_s between updates (not per
// IMU sample). With feedback, the error state of the forward pass is zero after each record; the
// smoother works on errors relative to the recorded nominal states:
//   e_N = 0, P^s_N = P^+_N;  for k = N-1 .. 0:
//     G_k   = P^+_k Phi_{k+1}^T (P^-_{k+1})^-1
//     e_k   = G_k (e_{k+1} + dx_{k+1})          (dx: the correction fed back at k+1, which moves
//                                                 the error from the posterior to the prior nominal)
//     P^s_k = P^+_k + G_k (P^s_{k+1} - P^-_{k+1}) G_k^T
// and the smoothed state at k is the recorded nominal corrected by e_k (sensor estimates too).
// Output at the IMU rate: from each smoothed record the IMU (corrected with the smoothed sensor
// errors of that record) is re-mechanized to the next record; the mismatch with the next
// smoothed state is removed linearly in time over the interval, so the output is continuous and
// equals the smoothed state at each record. Sigma is interpolated linearly between records.

#include <vector>

#include "graftnav/filters/ekf.h"

namespace graftnav {

struct SmoothedRecord {
  double t_s = 0.0;
  NavState nav;
  ImuErrorEstimate sensors;
  ErrorCov P = ErrorCov::Zero();
};

std::vector<SmoothedRecord> smoothRecords(const std::vector<SmootherRecord>& records);

struct RtsStats {
  size_t records = 0;
  size_t record_bytes = 0;  // memory held by the forward-pass records
};

// Forward EKF, then the smoother, then IMU-rate output. `forward` (optional) receives the
// forward solution of the same run.
NavSolution runRts(const EstimationProblem& problem, const EkfOptions& options,
                   NavSolution* forward = nullptr, RtsStats* stats = nullptr,
                   const ProgressFn& progress = {});

}  // namespace graftnav
