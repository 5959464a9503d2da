#pragma once
// Increments sampled exactly from an analytic integral, for synthetic IMU test signals.
#include <Eigen/Core>

#include "graftnav/nav/types.h"

namespace graftnav::test {

// integral(t) returns the integral over (0, t] of [omega_b (3); f_b (3)]; the samples are its
// differences over (t_{k-1}, t_k], tagged t0_s + t_k, at rate_hz for duration_s.
template <typename IntegralFn>
ImuSeries sampleIntegral(const IntegralFn& integral, double rate_hz, double duration_s,
                         double t0_s) {
  ImuSeries out;
  const int n = static_cast<int>(duration_s * rate_hz);
  out.reserve(n);
  Eigen::Matrix<double, 6, 1> prev = integral(0.0);
  for (int k = 1; k <= n; ++k) {
    const Eigen::Matrix<double, 6, 1> cur = integral(k / rate_hz);
    ImuSample s;
    s.t_s = t0_s + k / rate_hz;
    s.dt_s = 1.0 / rate_hz;
    s.dtheta_rad = (cur - prev).head<3>();
    s.dvel_m_s = (cur - prev).tail<3>();
    out.push_back(s);
    prev = cur;
  }
  return out;
}

}  // namespace graftnav::test
