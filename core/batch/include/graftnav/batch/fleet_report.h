#pragma once
// Fleet reports from a collected database (results_db.h), written after every local run, after
// --collect and on demand (--report). Like the summaries they hold no timing, so a local and a
// cluster run of one manifest write the same bytes.
//   report.md                 the four sections below, the headline numbers
//   report_estimators.csv     per group, option values, schedule, estimator and solution: each
//                             outage, check point and reference statistic across the cases (and
//                             seeds) as a distribution: n, min, p25, median, p75, max, mean
//   report_options.csv        per option axis and value: a statistic's mean, SD, min and max over
//                             cases and seeds (pooled over the group's other axes)
//   report_crosscheck.csv     per compare task and estimator pair: the difference inside the
//                             outages and the difference weighed by its own sigma
//                             (cross_check.h in core/eval), flagged beyond 3 sigma
//   report_failed.csv         failed and missing tasks with their messages
// The plots (report_*.png) are drawn from these CSVs by plot_batch.py.

#include <string>
#include <vector>

#include "graftnav/batch/results_db.h"

namespace graftnav {

// Normalized differences above this are a disagreement of the pair.
inline constexpr double kCrossCheckLimitSigma = 3.0;

void writeFleetReports(const std::string& out_dir, const std::vector<BatchTaskResult>& rows);

// The q-quantile (0..1) of sorted values, linear between order statistics.
double quantileOfSorted(const std::vector<double>& sorted, double q);

}  // namespace graftnav
