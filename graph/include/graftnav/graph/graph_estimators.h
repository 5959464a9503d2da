#pragma once
// The estimators of graph/ in the estimator table: "fgo" (batch factor-graph smoother) and
// "fgo-window" (sliding window with marginalization, causal output). They estimate IMU scale
// factors, and write imu_errors.txt, when FgoOptions::imu_scale_states says so for the run.
#include "graftnav/estimation/estimator_registry.h"

namespace graftnav {

void addGraphEstimators(EstimatorRegistry* registry);

}  // namespace graftnav
