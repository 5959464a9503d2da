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
// With the odometer scale state (ekf.h) the same recursion runs on 22 states.
// Output at the IMU rate: from each smoothed record the IMU (corrected with the smoothed sensor
// errors of that record) is re-mechanized to the next record; the mismatch with the next
// smoothed state is removed linearly in time over the interval, so the output is continuous and
// equals the smoothed state at each record. Sigma is interpolated linearly between records.

#include <vector>

#include "graftnav/filters/ekf.h"
#include "graftnav/estimation/solution_sink.h"
#include "graftnav/nav/mechanization.h"

namespace graftnav {

struct SmoothedRecord {
  double t_s = 0.0;
  NavState nav;
  ImuErrorEstimate sensors;
  ErrorCov P = ErrorCov::Zero();
  // The odometer scale factor and its 1-sigma, when the forward pass estimated it.
  bool has_scale = false;
  double scale = 0.0, scale_std = 0.0;
};

std::vector<SmoothedRecord> smoothRecords(const SmootherRecords& records);

// The IMU-rate output of the smoothed records, one IMU sample at a time (the second pass over
// the samples, from memory or re-read from the file in blocks): holds the smoothed records and
// the states of one record interval, never every sample's state.
class RtsOutputPass {
 public:
  RtsOutputPass(std::vector<SmoothedRecord> smoothed, int output_decimation, int gnss_week);
  // Next sample (times increasing). Samples up to the first record and after the last are not
  // output. The epochs of a record interval go to `sink` when the interval is complete.
  void add(const ImuSample& sample, SolutionSink& sink);
  // Emits the last open interval.
  void finish(SolutionSink& sink);

 private:
  // Moves to the next record interval of positive length at or after k (false: none left).
  bool openInterval(std::size_t k);
  void closeInterval(SolutionSink& sink);

  std::vector<SmoothedRecord> sm_;
  std::size_t decimation_;
  int gnss_week_;
  std::size_t k_ = 0;     // current interval [sm_[k_], sm_[k_ + 1]]
  bool started_ = false;  // the samples up to the first record are behind
  bool open_ = false;
  Strapdown strapdown_;
  std::vector<NavState> buffer_;  // this interval's mechanized states
  std::size_t processed_ = 0;
};

// Forward EKF, smoother and IMU-rate output with two passes over `imu` (problem.imu is not read):
// memory holds the records (one per GNSS update or record_interval_s), never every sample's
// state. Returns the GNSS bookkeeping (no states); the epochs equal runRts's.
NavSolution runRtsStreaming(const EstimationProblem& problem, const EkfOptions& options,
                            const ImuPassFn& imu, SolutionSink& sink);

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
