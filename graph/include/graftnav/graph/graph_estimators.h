#pragma once
// The estimators of graph/ in the estimator table: "fgo" (batch factor-graph smoother) and
// "fgo-window" (sliding window with marginalization, causal output). Neither estimates scale
// factors, so a run of either writes no imu_errors.txt.
#include "graftnav/estimation/estimator_registry.h"

namespace graftnav {

void addGraphEstimators(EstimatorRegistry* registry);

}  // namespace graftnav
