#pragma once
// Two solutions of one drive compared from their spools (solution_spool.h), read as streams and
// joined on time by StreamedEvaluation: number for number the in-memory forms
// evaluateSolution(a, b.states, outages) and crossCheck(a, b, outages, form) (cross_check.h),
// with memory that does not grow with the drive.
#include <vector>

#include "graftnav/eval/cross_check.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/solution_spool.h"
#include "graftnav/nav/time_window.h"

namespace graftnav {

// a evaluated against b as the reference (default options; statistics only, no epochs).
Evaluation evaluatePair(const SolutionSpool& a, const SolutionSpool& b,
                        const std::vector<TimeWindow>& outages);

// The cross-check of a and b (b smooths a's filter for kFilterSmoother). Throws
// std::invalid_argument when the solutions do not overlap in time.
CrossCheck crossCheck(const SolutionSpool& a, const SolutionSpool& b,
                      const std::vector<TimeWindow>& outages, DifferenceCovariance form);

}  // namespace graftnav
