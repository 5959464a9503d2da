#pragma once
// The batch summaries, written from the collected results database (results_db.h) so that a
// local run and a cluster run of one manifest give the same bytes. Nothing in them depends on
// timing or on where the tasks ran.
//   summary.csv                  every statistic of every task, one row each (failed and missing
//                                tasks one row with their status and message)
//   summary.md                   one table per group, the columns its command reports
//   summary_monte_carlo.csv/.md  evaluate and real-sg: seeds of one experiment (same case name
//                                up to a trailing _seed<N>, estimator, schedule, options)
//                                averaged, when any experiment has more than one realization

#include <string>
#include <vector>

#include "graftnav/batch/results_db.h"

namespace graftnav {

void writeBatchSummaries(const std::string& out_dir, const std::vector<BatchTaskResult>& rows);

// Monte-Carlo groups: case names that differ only by a trailing "_seed<N>" are realizations of
// one experiment.
std::string experimentName(const std::string& case_name);

// A CSV field: as is, or double-quoted (quotes doubled) when it holds a comma, quote or newline.
std::string csvField(const std::string& s);

// The value of one statistic of a task (NaN when it has none).
double statisticValue(const BatchTaskResult& r, const std::string& solution,
                      const std::string& scope, const std::string& statistic,
                      const std::string& measure);

}  // namespace graftnav
