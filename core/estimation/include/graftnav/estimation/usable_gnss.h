#pragma once
// The fixes an estimator may use, read in one pass: the problem's fixes (its stream when set,
// else its series) in time order, those inside its outages skipped and counted. Holds one fix,
// whatever the recording's length.

#include <memory>

#include "graftnav/estimation/nav_solution.h"

namespace graftnav {

class UsableGnss {
 public:
  // Opens a pass over `problem`'s fixes (the problem must outlive this).
  explicit UsableGnss(const EstimationProblem& problem);
  // The next usable fix, or null at the end. Throws std::invalid_argument naming both times when
  // a fix is earlier than the one before it.
  const GnssFix* peek();
  // Moves past the fix peek() returned.
  void pop() { has_ = false; }
  // Reads to the end, so that withheld() counts every fix of the problem.
  void skipRest();
  int withheld() const { return withheld_; }

 private:
  const EstimationProblem& problem_;
  std::unique_ptr<GnssSource> source_;
  GnssFix fix_;
  bool has_ = false, ended_ = false, any_ = false;
  double t_prev_ = 0.0;
  int withheld_ = 0;
};

}  // namespace graftnav
