#pragma once
// Two estimators' solutions of one drive compared inside the GNSS outages, the difference weighed
// by its own sigma: do they disagree by more than their covariances say they may?
//
// d = x_a - x_b at each epoch of a inside an outage (b interpolated). Its variance per component:
//   * b is the RTS smoother of a's own forward filter (ekf and rts): var(d) = P_a - P_b exactly,
//     because the smoothed error is orthogonal to everything the data decide, x_b - x_a among
//     them (P_a = P_b + cov(x_b - x_a)). The two are correlated; P_a + P_b would be far too wide.
//   * any other pair (ekf and fgo, rts and fgo-window ...): P_a + P_b, which is an upper bound
//     while the two errors are positively correlated (both read the same IMU and GNSS):
//     var(d) = P_a + P_b - 2 cov(a, b). The normalized difference is then understated, so this
//     form over-states agreement; a pair flagged with it disagrees for sure.
// Normalized: horizontal |d_NE| / sqrt(var_N + var_E) (its square has mean 1 when consistent),
// vertical |d_D| / sigma_D, heading |d_psi| / sigma_psi (rotation about down).

#include <limits>
#include <vector>

#include "graftnav/estimation/nav_solution.h"
#include "graftnav/nav/time_window.h"

namespace graftnav {

enum class DifferenceCovariance {
  kFilterSmoother,  // b smooths a's forward filter: P_a - P_b
  kIndependent,     // P_a + P_b, an upper bound
};
// "filter-smoother" / "sum-upper-bound", the words of compare.json and the batch database.
const char* differenceCovarianceName(DifferenceCovariance form);

struct CrossCheckStat {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double rms_difference = kNaN;      // RMS over outage epochs of |d| (m; rad for heading)
  double rms_sigma = kNaN;           // RMS of the difference's sigma over the epochs that have one
  double rms_normalized = kNaN;      // RMS of |d| / sigma (1 when the sigmas are right)
  double max_normalized = kNaN;      // its maximum
  double max_normalized_t_s = kNaN;  // where the maximum is
  int epochs = 0;                    // outage epochs compared
  int normalized_epochs = 0;         // of them, with a positive variance of the difference
};

struct CrossCheck {
  DifferenceCovariance form = DifferenceCovariance::kIndependent;
  bool has_sigma = false;  // both solutions carry sigmas (else only the differences)
  CrossCheckStat horizontal, vertical, heading;
  // The largest normalized difference of the three (NaN without sigmas).
  double maxNormalized() const;
};

// Throws std::invalid_argument when the solutions do not overlap in time.
CrossCheck crossCheck(const NavSolution& a, const NavSolution& b,
                      const std::vector<TimeWindow>& outages, DifferenceCovariance form);

}  // namespace graftnav
