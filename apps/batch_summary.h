#pragma once
// The batch summaries, written from the collected results database (batch_db.h) so that a local
// run and a cluster run of one manifest give the same bytes:
//   summary.csv / summary.md                    one row per task (status ok, failed or missing)
//   summary_monte_carlo.csv / .md               seeds of one experiment averaged (when any
//                                               experiment has more than one realization)
// Nothing in them depends on timing or on where the tasks ran.
#include <string>
#include <vector>

#include "batch_db.h"

namespace graftnav::app {

void writeBatchSummaries(const std::string& out_dir, const std::vector<BatchSummaryRow>& rows);

// Monte-Carlo groups: tasks whose case names differ only by a trailing "_seed<N>", with the same
// estimator and schedule, over every grafting seed, are realizations of one experiment.
std::string experimentName(const std::string& case_name);

}  // namespace graftnav::app
