#pragma once
// Shared by the IMU error model tests: exactly integrated increment series and test inputs.
#include <functional>

#include "graftnav/imu/imu_error_model.h"

namespace graftnav::imu_test {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using IntervalFn = std::function<Vector3d(double, double)>;  // integral over [t0, t1]

inline constexpr double kPi = 3.14159265358979323846;

// Samples k = 0..n-1 covering [t_start + k dt, t_start + (k+1) dt], increments from exact
// integrals.
inline ImuSeries makeSeries(int n, double dt, const IntervalFn& dtheta, const IntervalFn& dvel,
                            double t_start = 1000.0) {
  ImuSeries s(n);
  for (int k = 0; k < n; ++k) {
    const double t0 = t_start + k * dt;
    const double t1 = t_start + (k + 1) * dt;
    s[k].t_s = t1;
    s[k].dt_s = dt;
    s[k].dtheta_rad = dtheta(t0, t1);
    s[k].dvel_m_s = dvel(t0, t1);
  }
  return s;
}

inline IntervalFn constantRate(const Vector3d& x) {
  return [x](double t0, double t1) { return Vector3d(x * (t1 - t0)); };
}

// Constant inputs with increments exactly x * dt (no rounding of time differences).
inline ImuSeries constantSeries(int n, double dt, const Vector3d& omega, const Vector3d& f) {
  ImuSeries s(n);
  for (int k = 0; k < n; ++k) {
    s[k].t_s = 1000.0 + (k + 1) * dt;
    s[k].dt_s = dt;
    s[k].dtheta_rad = omega * dt;
    s[k].dvel_m_s = f * dt;
  }
  return s;
}

inline const Vector3d kOmega(0.12, -0.31, 0.47);  // rad/s
inline const Vector3d kF(0.8, -1.3, -9.79);       // m/s^2

}  // namespace graftnav::imu_test
