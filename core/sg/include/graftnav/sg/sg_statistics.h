#pragma once
// The seed's verification statistics (Sec. 3.1, Eq. 24-25): ERR_x are a solution's drift
// statistics against SOL_REF (DriftStats of evaluation.h, RMS over outage epochs), and
//   DIFF_x = |ERR_x - ERR_REAL| / ERR_REAL,
// a fraction per statistic (horizontal, vertical, roll, pitch, heading).

#include <array>
#include <string>

#include "graftnav/eval/evaluation.h"

namespace graftnav {

// The five statistics in the seed's column order, SI (m, rad).
std::array<double, 5> asArray(const DriftStats& s);
DriftStats fromArray(const std::array<double, 5>& a);
// Column names with units for reports: horizontal_m, vertical_m, roll_deg, pitch_deg, heading_deg.
const std::array<std::string, 5>& driftStatNames();

// DIFF per statistic (fraction). A statistic whose ERR_REAL is zero or NaN gives NaN.
DriftStats relativeDifference(const DriftStats& err_x, const DriftStats& err_real);

}  // namespace graftnav
