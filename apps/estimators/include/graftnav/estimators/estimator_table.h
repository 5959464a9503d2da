#pragma once
// The full estimator table: filters/ (ekf, rts, free-inertial) and graph/ (fgo, fgo-window) in
// one EstimatorRegistry (graftnav/estimation/estimator_registry.h). The only code that needs both
// filters/ and graph/; the `graftnav` command and the Python module link it (graftnav::estimators)
// and hand the table to the core code that runs an estimator on a case.
#include "graftnav/estimation/estimator_registry.h"

namespace graftnav {

// Built once, on first use; immutable afterwards (safe to read from several threads).
const EstimatorRegistry& estimatorTable();

}  // namespace graftnav
