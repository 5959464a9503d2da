#pragma once
// Free-inertial navigation: the IMU mechanized from the problem's initial state with no GNSS and
// no error estimation. Sensor errors are not compensated; sigma is left empty.

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/filters/ekf.h"

namespace graftnav {

NavSolution runFreeInertial(const EstimationProblem& problem, int output_decimation = 1,
                            const ProgressFn& progress = {});

}  // namespace graftnav
