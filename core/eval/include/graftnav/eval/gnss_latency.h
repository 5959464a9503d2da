#pragma once
// GNSS time-tag latency from the data, and errors of a navigation solution at withheld GNSS
// check points.
//
// Model: a fix stamped t_tag is the antenna position at t_tag - tau (tau > 0: the receiver stamps
// the receive/output time, later than the measurement). With an independent track p(t) of the
// antenna (an IMU-propagated solution that did NOT use these fixes, or a reference solution), the
// residual of a fix for a trial shift s is
//     r(s) = p_fix - p(t_tag - s)        (NED, metres)
// and, to first order, r(s) = v (s - tau) + noise + track error, v the track velocity. Two
// estimates of tau:
//   grid:  the shift minimizing the horizontal RMS of r(s) over a grid (refined by a parabola
//          through the minimum and its neighbours) - robust to large shifts and turns;
//   slope: least squares of r(0) on -v:  tau = -sum(v_h . r_h(0)) / sum(|v_h|^2) - exact for a
//          straight track, biased by track errors that correlate with velocity.
// Only fixes where the track speed exceeds min_speed_m_s carry information (at rest r does not
// depend on s); fixes whose horizontal residual at the best shift exceeds outlier_m are dropped
// and the estimate repeated once. Track errors (e.g. a track aided by single-point GNSS with its
// own latency) enter the estimate: tau is relative to the track's time base.
// The offset between two IMU records is estimated elsewhere (mismatch/time_offset.h, by the
// cross-correlation of the dense rate signals); sparse fixes against a track have no such
// correlation, hence this residual scan (the reason is stated there).

#include <Eigen/Core>
#include <vector>

#include "graftnav/eval/outage_schedule.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct FixResidual {
  double t_s = 0.0;                                     // fix time tag (as given)
  Eigen::Vector3d r_ned_m = Eigen::Vector3d::Zero();    // fix minus track antenna position (NED)
  Eigen::Vector3d v_ned_m_s = Eigen::Vector3d::Zero();  // track velocity at the evaluated time
  int fix_type = 0;
};

// The residual of `fix` against the antenna position of `track_state` (IMU position + C_nb lever
// arm), the track's state at the time the fix is compared at.
FixResidual fixResidual(const GnssFix& fix, const NavState& track_state,
                        const Eigen::Vector3d& lever_arm_b_m);

// Residuals of `fixes` against the antenna position of `track` (IMU position + C_nb lever arm)
// evaluated at t_tag - shift_s. Fixes outside the track span are skipped.
std::vector<FixResidual> fixResiduals(const NavSeries& track, const GnssSeries& fixes,
                                      double shift_s, const Eigen::Vector3d& lever_arm_b_m);

struct LatencyScanOptions {
  double min_shift_s = -1.5;
  double max_shift_s = 1.5;
  double step_s = 0.02;
  double min_speed_m_s = 3.0;
  double outlier_m = 5.0;  // horizontal residual at the best shift above which a fix is dropped
  void validate() const;   // throws std::invalid_argument naming the field
};

struct LatencyEstimate {
  std::vector<double> shift_s;   // grid
  std::vector<double> rms_h_m;   // horizontal RMS of r(shift) over the used fixes
  double grid_s = 0.0;           // grid estimate (parabola-refined)
  double grid_rms_h_m = 0.0;     // RMS at the nearest grid point
  double rms_h_at_zero_m = 0.0;  // RMS without correction (shift 0, or nearest grid point)
  double slope_s = 0.0;          // least-squares along-track estimate
  int fixes_used = 0;
  int fixes_slow = 0;  // below min_speed_m_s
  int fixes_outliers = 0;
};

// Throws std::invalid_argument when fewer than 3 fixes are usable.
LatencyEstimate estimateGnssLatency(const NavSeries& track, const GnssSeries& fixes,
                                    const Eigen::Vector3d& lever_arm_b_m,
                                    const LatencyScanOptions& options = {});

// Errors (solution minus fix) at check points: fixes withheld inside outage windows.
struct CheckpointWindowStats {
  TimeWindow window;
  int n = 0;
  double rms_h_m = 0.0, max_h_m = 0.0, rms_v_m = 0.0, max_v_m = 0.0;
  double last_h_m = 0.0;  // at the last check point of the window
};

struct CheckpointEvaluation {
  std::vector<CheckpointWindowStats> windows;  // windows with at least one check point
  int n = 0;
  double rms_h_m = 0.0, rms_v_m = 0.0;                // over all check points
  double rms_of_max_h_m = 0.0, rms_of_max_v_m = 0.0;  // over windows, of the per-window maximum
  double mean_of_max_h_m = 0.0;
};

// One window's statistics built one residual at a time (the residuals in time order); the RMS
// fields are set by checkpointEvaluation.
struct CheckpointWindowSums {
  CheckpointWindowStats stats;
  double sum_h2_m2 = 0.0, sum_v2_m2 = 0.0;
  void add(const FixResidual& r);
};

// The evaluation from each window's sums, in window order (windows without a check point left
// out).
CheckpointEvaluation checkpointEvaluation(const std::vector<CheckpointWindowSums>& windows);

CheckpointEvaluation evaluateAtCheckpoints(const NavSeries& solution, const GnssSeries& checkpoints,
                                           const std::vector<TimeWindow>& windows,
                                           const Eigen::Vector3d& lever_arm_b_m);

}  // namespace graftnav
