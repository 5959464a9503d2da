#pragma once
// Ideal IMU: increments over (t_{k-1}, t_k] that are exact time integrals of omega_ib_b(t) and
// f_b(t) of a Trajectory, by Gauss-Legendre quadrature. This is what a real IMU outputs (integrated
// body-frame rates); coning and sculling are the mechanization's business, not the simulator's.

#include <functional>
#include <vector>

#include "graftnav/sim/trajectory.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// Gauss-Legendre rule on [-1, 1] with n nodes (Newton on the Legendre recurrence, |err| ~ 1e-16).
struct GaussLegendreRule {
  std::vector<double> nodes;
  std::vector<double> weights;
};
GaussLegendreRule gaussLegendreRule(int n);

struct IdealImuOptions {
  double rate_hz = 200.0;    // output rate; sample k ends at t_begin + k / rate_hz
  int quadrature_nodes = 6;  // Gauss-Legendre nodes per interval (exact for degree 2n-1)
  // Where the sensor sits relative to the trajectory's point, body frame (m): a rigid-body point
  // at r feels f_b + omega_dot x r + omega x (omega x r) (omega = omega_ib_b; the gravity
  // gradient over r is left out).
  Eigen::Vector3d lever_arm_b_m = Eigen::Vector3d::Zero();
  void validate() const;  // throws std::invalid_argument naming the bad field
};

// The increment over (t0_s, t1_s] of a sensor at lever_arm_b_m from the trajectory's point. The
// lever arm's velocity increment is exact: (omega(t1) - omega(t0)) x r from the instantaneous
// rates at the ends, plus the quadrature of omega x (omega x r), so road vibration near Nyquist
// keeps its full tangential term (an increment series' interpolated node rates lose most of it).
ImuSample idealImuSample(const Trajectory& trj, double t0_s, double t1_s,
                         const GaussLegendreRule& rule,
                         const Eigen::Vector3d& lever_arm_b_m = Eigen::Vector3d::Zero());

// All samples ending at t_begin + k / rate, k = 1 .. floor((t_end - t_begin) rate).
// progress (optional) is called with the fraction done about every 1 %.
ImuSeries simulateIdealImu(const Trajectory& trj, double t_begin_s, double t_end_s,
                           const IdealImuOptions& opt = {},
                           const std::function<void(double)>& progress = {});

// Truth states at t_begin + k * decimation / rate, k = 0, 1, ... (includes the initial epoch).
NavSeries sampleTruth(const Trajectory& trj, double t_begin_s, double t_end_s, double rate_hz,
                      int gnss_week);

}  // namespace graftnav
