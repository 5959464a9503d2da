#pragma once
// A series that arrives in time order, seen through a window of the epochs still needed, and the
// interpolation of such a series at increasing times that gives, state for state, what
// NavInterpolator (nav_interp.h) gives on the whole series: the same bracketing pair for every
// query, including its jump to a binary search when the query is 64 or more epochs ahead.
// Memory is the window, not the series.

#include <cstddef>
#include <deque>
#include <optional>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/nav/types.h"

namespace graftnav::eval_detail {

class SeriesWindow {
 public:
  struct Entry {
    NavState state;
    PvaSigma sigma;  // the solution's 1-sigma (unset for a reference)
  };

  // Appends the next epoch; throws std::invalid_argument (naming `what`) when its time is before
  // the previous epoch's (a series read whole would be searched backwards: not supported).
  void push(const NavState& state, const PvaSigma* sigma, const char* what);
  void end() { ended_ = true; }  // no more epochs
  bool ended() const { return ended_; }

  std::size_t count() const { return base_ + entries_.size(); }  // epochs pushed so far
  bool has(std::size_t index) const { return index >= base_ && index < count(); }
  const Entry& at(std::size_t index) const { return entries_[index - base_]; }
  const NavState& first() const { return first_; }  // kept when trimmed away
  const NavState& last() const { return last_; }    // kept when trimmed away
  bool empty() const { return count() == 0; }
  std::size_t held() const { return entries_.size(); }  // epochs in memory
  // Forgets the epochs before `index`.
  void trimBefore(std::size_t index);

 private:
  std::deque<Entry> entries_;
  std::size_t base_ = 0;  // index of entries_.front()
  NavState first_, last_;
  bool ended_ = false;
};

// NavInterpolator over a SeriesWindow.
class WindowInterpolator {
 public:
  explicit WindowInterpolator(const SeriesWindow& window, double tol_s = 1e-6)
      : w_(window), tol_s_(tol_s) {}
  // Whether at(t_s) can be answered from the epochs the window holds (always, once it ended).
  bool ready(double t_s) const;
  // The state at t_s, as NavInterpolator::at on the whole series. Requires ready(t_s) and times not
  // decreasing from one call to the next.
  std::optional<NavState> at(double t_s);
  // The lowest index the interpolator still needs.
  std::size_t index() const { return idx_; }

  static constexpr std::size_t kLookahead = 64;  // NavInterpolator's far-ahead test

 private:
  const SeriesWindow& w_;
  double tol_s_;
  std::size_t idx_ = 0;
};

}  // namespace graftnav::eval_detail
