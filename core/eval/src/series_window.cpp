#include "series_window.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "graftnav/nav/nav_interp.h"

namespace graftnav::eval_detail {

void SeriesWindow::push(const NavState& state, const PvaSigma* sigma, const char* what) {
  if (count() > 0 && state.t_s < last_.t_s) {
    throw std::invalid_argument(std::string(what) + " epoch " + std::to_string(count()) + " at " +
                                std::to_string(state.t_s) + " s is before the previous one (" +
                                std::to_string(last_.t_s) +
                                " s): a streamed evaluation needs times in order");
  }
  if (count() == 0) first_ = state;
  last_ = state;
  Entry e;
  e.state = state;
  if (sigma) e.sigma = *sigma;
  entries_.push_back(e);
}

void SeriesWindow::trimBefore(std::size_t index) {
  while (base_ < index && !entries_.empty()) {
    entries_.pop_front();
    ++base_;
  }
}

bool WindowInterpolator::ready(double t_s) const {
  if (w_.ended()) return true;
  return w_.has(idx_ + kLookahead) && w_.last().t_s > t_s + tol_s_;
}

std::optional<NavState> WindowInterpolator::at(double t_s) {
  if (w_.empty()) return std::nullopt;
  const bool ended = w_.ended();
  const std::size_t n = w_.count();  // the series' length once ended
  // Not ended: the window holds an epoch after t_s + tol, so t_s is before the series' last epoch.
  if (t_s < w_.first().t_s - tol_s_ || (ended && t_s > w_.last().t_s + tol_s_)) return std::nullopt;
  if ((ended && n == 1) || t_s <= w_.first().t_s) {
    NavState s = w_.first();
    s.t_s = t_s;
    return s;
  }
  if (ended && t_s >= w_.last().t_s) {
    NavState s = w_.last();
    s.t_s = t_s;
    return s;
  }
  const bool jump = (ended && idx_ + 1 >= n) || w_.at(idx_).state.t_s > t_s ||
                    (w_.has(idx_ + kLookahead) && w_.at(idx_ + kLookahead).state.t_s < t_s);
  if (jump) {
    // NavInterpolator's binary search over the whole series: the last epoch at or before t_s.
    // Every epoch before idx_ is at or before it (times never decrease), so the search starts
    // there.
    if (w_.at(idx_).state.t_s > t_s)
      throw std::logic_error("WindowInterpolator: a query before the window");
    std::size_t lo = idx_, hi = n;  // first epoch after t_s in [lo, hi)
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (w_.at(mid).state.t_s > t_s) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
    idx_ = lo - 1;
  }
  while (idx_ + 1 < n && w_.at(idx_ + 1).state.t_s < t_s) ++idx_;
  return interpolateBetween(w_.at(idx_).state, w_.at(std::min(idx_ + 1, n - 1)).state, t_s);
}

}  // namespace graftnav::eval_detail
