#pragma once
// The errors at withheld GNSS check points (evaluateAtCheckpoints, graftnav/eval/gnss_latency.h)
// while the estimator writes: the solution's epochs are added one at a time and each check point
// is compared with the solution interpolated at its time as soon as the epoch after it has come.
// The interpolation takes the very bracket NavInterpolator takes in evaluateAtCheckpoints (a
// fresh interpolator per outage window, its index carried from check point to check point), so
// the numbers are those of the in-memory evaluation bit for bit. Held: the check points, a window
// of the last kHeldEpochs solution epochs and the first one, and one set of sums per window.
#include <cstddef>
#include <deque>
#include <vector>

#include <Eigen/Core>

#include "graftnav/eval/gnss_latency.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/nav/types.h"

namespace graftnav {

class StreamedCheckpoints {
 public:
  static constexpr std::size_t kHeldEpochs = 256;

  // checkpoints strictly increasing in time (selectGnss's output); throws std::invalid_argument
  // otherwise. Only the check points inside a window are kept.
  StreamedCheckpoints(const GnssSeries& checkpoints, const std::vector<TimeWindow>& windows,
                      const Eigen::Vector3d& lever_arm_b_m);

  // The next solution epoch (times not decreasing).
  void add(const NavState& state);
  // Ends the solution: the check points after its last epoch are evaluated and the statistics
  // returned.
  CheckpointEvaluation finish();

 private:
  // One window's pending check points and the state of its interpolator.
  struct Window {
    std::vector<GnssFix> fixes;
    std::size_t next = 0;   // first check point not evaluated yet
    std::size_t index = 0;  // the interpolator's bracket index (NavInterpolator::idx_)
    CheckpointWindowSums sums;
    std::vector<FixResidual> before_second;  // evaluated before the solution's second epoch
  };
  const NavState& held(std::size_t index) const;
  // The solution's state at fix time t_s, strictly inside the epochs seen (the last one after t_s).
  NavState bracketState(Window* w, double t_s) const;
  void record(Window* w, const FixResidual& r) const;

  std::vector<Window> windows_;
  std::vector<std::size_t> by_start_;  // window indices by start time
  std::size_t first_open_ = 0;         // in by_start_: windows before it are done
  Eigen::Vector3d lever_arm_b_m_;
  NavState first_;
  std::deque<NavState> recent_;  // the last epochs, recent_.back() has index count_ - 1
  std::size_t count_ = 0;
};

}  // namespace graftnav
