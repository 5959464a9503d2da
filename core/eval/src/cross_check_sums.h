#pragma once
// The sums of one compared quantity of the cross-check over the outage epochs, shared by its
// in-memory and spooled forms (cross_check.cpp, cross_check_spooled.cpp).
#include <cmath>

#include "graftnav/eval/cross_check.h"

namespace graftnav::cross_check_detail {

// Indices of the sigma vector (nav_solution.h): position N, E, D; attitude about down.
constexpr int kPosN = 0, kPosE = 1, kPosD = 2, kAttD = 8;

struct StatSum {
  double d2 = 0.0, s2 = 0.0, z2 = 0.0, z_max = -1.0, t_max = 0.0;
  int n = 0, n_z = 0;
  void add(double t_s, double d, double var) {
    d2 += d * d;
    ++n;
    if (!(var > 0.0) || !std::isfinite(var)) return;
    const double z = std::abs(d) / std::sqrt(var);
    s2 += var;
    z2 += z * z;
    ++n_z;
    if (z > z_max) {
      z_max = z;
      t_max = t_s;
    }
  }
  CrossCheckStat stat() const {
    CrossCheckStat s;
    s.epochs = n;
    s.normalized_epochs = n_z;
    if (n > 0) s.rms_difference = std::sqrt(d2 / n);
    if (n_z > 0) {
      s.rms_sigma = std::sqrt(s2 / n_z);
      s.rms_normalized = std::sqrt(z2 / n_z);
      s.max_normalized = z_max;
      s.max_normalized_t_s = t_max;
    }
    return s;
  }
};

}  // namespace graftnav::cross_check_detail
