#pragma once
// The estimators of filters/ in the estimator table: "ekf" (forward closed-loop 21-state EKF),
// "rts" (EKF + Rauch-Tung-Striebel smoother) and "free-inertial" (mechanization, no GNSS).
#include "graftnav/estimation/estimator_registry.h"

namespace graftnav {

void addFilterEstimators(EstimatorRegistry* registry);

}  // namespace graftnav
