#include "graftnav/navigate/streamed_checkpoints.h"

#include <algorithm>
#include <stdexcept>

#include "graftnav/nav/nav_interp.h"

namespace graftnav {
namespace {

// NavInterpolator's tolerance at the ends of the series and its look-ahead: a query more than
// this many epochs past the bracket index is found by binary search.
constexpr double kEndTolerance_s = 1e-6;
constexpr std::size_t kLookAheadEpochs = 64;

}  // namespace

StreamedCheckpoints::StreamedCheckpoints(const GnssSeries& checkpoints,
                                         const std::vector<TimeWindow>& windows,
                                         const Eigen::Vector3d& lever_arm_b_m)
    : lever_arm_b_m_(lever_arm_b_m) {
  for (std::size_t k = 1; k < checkpoints.size(); ++k)
    if (!(checkpoints[k].t_s > checkpoints[k - 1].t_s))
      throw std::invalid_argument("StreamedCheckpoints: check point times must increase");
  for (const TimeWindow& w : windows) {
    Window win;
    win.sums.stats.window = w;
    for (const GnssFix& f : checkpoints)
      if (f.t_s >= w.start_s && f.t_s <= w.end_s) win.fixes.push_back(f);
    windows_.push_back(std::move(win));
    by_start_.push_back(by_start_.size());
  }
  std::stable_sort(by_start_.begin(), by_start_.end(), [&](std::size_t a, std::size_t b) {
    return windows_[a].sums.stats.window.start_s < windows_[b].sums.stats.window.start_s;
  });
}

const NavState& StreamedCheckpoints::held(std::size_t index) const {
  const std::size_t oldest = count_ - recent_.size();
  if (index < oldest || index >= count_)
    throw std::logic_error("StreamedCheckpoints: epoch no longer held (more than " +
                           std::to_string(kHeldEpochs) + " epochs with one time)");
  return recent_[index - oldest];
}

NavState StreamedCheckpoints::bracketState(Window* w, double t_s) const {
  const std::size_t last = count_ - 1;  // the first epoch after t_s
  const std::size_t oldest = count_ - recent_.size();
  std::size_t idx = w->index;
  // NavInterpolator::at: a backward query, or one more than kLookAheadEpochs past the index, is
  // searched (upper bound - 1: the epoch before `last`). An index no longer held lies further
  // back than the look-ahead, at an epoch before t_s.
  bool search = idx < oldest || held(idx).t_s > t_s;
  if (!search && idx + kLookAheadEpochs <= last) search = held(idx + kLookAheadEpochs).t_s < t_s;
  if (search) idx = last - 1;
  while (held(idx + 1).t_s < t_s) ++idx;
  w->index = idx;
  return interpolateBetween(held(idx), held(idx + 1), t_s);
}

void StreamedCheckpoints::record(Window* w, const FixResidual& r) const {
  // fixResiduals gives none for a solution of fewer than two epochs.
  if (count_ < 2) {
    w->before_second.push_back(r);
  } else {
    w->sums.add(r);
  }
}

void StreamedCheckpoints::add(const NavState& state) {
  if (count_ == 0) first_ = state;
  recent_.push_back(state);
  if (recent_.size() > kHeldEpochs) recent_.pop_front();
  ++count_;
  if (count_ == 2) {
    for (Window& w : windows_) {
      for (const FixResidual& r : w.before_second) w.sums.add(r);
      w.before_second.clear();
    }
  }
  // Every check point before this epoch is evaluated now: the epoch before it is held.
  for (std::size_t k = first_open_; k < by_start_.size(); ++k) {
    Window& w = windows_[by_start_[k]];
    if (w.sums.stats.window.start_s >= state.t_s) break;
    for (; w.next < w.fixes.size() && w.fixes[w.next].t_s < state.t_s; ++w.next) {
      const GnssFix& f = w.fixes[w.next];
      if (f.t_s < first_.t_s - kEndTolerance_s) continue;
      NavState s = first_;
      s.t_s = f.t_s;
      if (f.t_s > first_.t_s) s = bracketState(&w, f.t_s);
      record(&w, fixResidual(f, s, lever_arm_b_m_));
    }
  }
  while (first_open_ < by_start_.size() &&
         windows_[by_start_[first_open_]].next == windows_[by_start_[first_open_]].fixes.size())
    ++first_open_;
}

CheckpointEvaluation StreamedCheckpoints::finish() {
  if (count_ < 2) return {};
  const NavState& back = recent_.back();
  std::vector<CheckpointWindowSums> sums;
  for (Window& w : windows_) {
    // What is left lies at or after the last epoch: the first or the last state, as NavInterpolator
    // gives at the ends.
    for (; w.next < w.fixes.size(); ++w.next) {
      const GnssFix& f = w.fixes[w.next];
      if (f.t_s < first_.t_s - kEndTolerance_s || f.t_s > back.t_s + kEndTolerance_s) continue;
      NavState s = f.t_s <= first_.t_s ? first_ : back;
      s.t_s = f.t_s;
      w.sums.add(fixResidual(f, s, lever_arm_b_m_));
    }
    sums.push_back(w.sums);
  }
  return checkpointEvaluation(sums);
}

}  // namespace graftnav
