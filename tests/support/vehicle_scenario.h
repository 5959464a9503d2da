#pragma once
// A car drive for the vehicle-aiding tests of filters/ and graph/: the simulator's motion script
// (6 min at 100 Hz, accelerations and turns both ways, 6-16 m/s), a MEMS IMU with injected
// biases and scale factors, 1 Hz RTK-grade GNSS with a 60 s outage, and the simulator's
// odometer at 10 Hz, 3000 ppm fast with 0.05 m/s white noise (lever arm and mounting zero).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ekf_scenario.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/nav/earth.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/sim/motion_script.h"
#include "graftnav/sim/odometer_simulator.h"

namespace graftnav::test {

constexpr double kVehicleDriveScaleError = 3000e-6;

struct VehicleDrive {
  NavSeries truth;  // at the initial time and at the end of every IMU sample (100 Hz)
  EstimationProblem problem;
  TimeWindow outage;
};

inline VehicleDrive makeVehicleDrive() {
  MotionScript m;
  m.start_time_s = 200000.0;
  m.start = {30.5 * kDegToRad, 114.3 * kDegToRad, 20.0};
  m.initial_yaw_rad = 0.4;
  using T = MotionSegment::Type;
  m.segments = {{T::kAccelerate, 15.0, 10.0},
                {T::kCruise, 20.0},
                {T::kTurn, 9.0, 0.0, 10 * kDegToRad},
                {T::kAccelerate, 10.0, 16.0},
                {T::kCruise, 30.0},
                {T::kTurn, 12.0, 0.0, -8 * kDegToRad},
                {T::kAccelerate, 15.0, 6.0},
                {T::kTurn, 15.0, 0.0, 15 * kDegToRad},
                {T::kAccelerate, 15.0, 14.0},
                {T::kCruise, 40.0},
                {T::kTurn, 10.0, 0.0, -12 * kDegToRad},
                {T::kCruise, 60.0},
                {T::kTurn, 10.0, 0.0, 9 * kDegToRad},
                {T::kAccelerate, 20.0, 9.0},
                {T::kCruise, 60.0},
                {T::kTurn, 10.0, 0.0, -10 * kDegToRad},
                {T::kCruise, 40.0}};
  const ScriptTrajectory trj(m);
  VehicleDrive d;
  const double t0 = trj.startTime_s(), t1 = trj.endTime_s();
  IdealImuOptions io;
  io.rate_hz = 100.0;
  const ImuSeries ideal = simulateIdealImu(trj, t0, t1, io);
  d.truth = sampleTruth(trj, t0, t1, 100.0, 2100);
  const ImuProfile prof = memsProfile();
  InjectedErrors e;
  e.gyro_bias_rad_s << 8e-5, -5e-5, 6e-5;  // ~15 deg/h
  e.accel_bias_m_s2 << 0.01, -0.008, 0.012;
  e.gyro_scale.setConstant(500e-6);
  e.accel_scale.setConstant(-400e-6);
  EstimationProblem& p = d.problem;
  p.imu = corrupt(ideal, e, prof, 21);
  p.imu_profile = prof;
  p.initial = d.truth.front();
  p.lever_arm_b_m << 0.3, -0.2, -1.2;
  p.gnss = makeGnss(d.truth, p.lever_arm_b_m, 100, 0.02, 22);
  p.initial_sigma << 0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.1 * kDegToRad, 0.1 * kDegToRad,
      0.5 * kDegToRad;
  d.outage = {t0 + 200.0, t0 + 260.0};
  p.outages = {d.outage};
  OdometerSimOptions o;
  o.scale_error = kVehicleDriveScaleError;
  o.noise_std_m_s = 0.05;
  p.odometer = simulateOdometer(trj, t0, t1, o, 23);
  return d;
}

// Odometer (forward 0.05 m/s, scale sigma 1 %) and NHC (0.05 m/s) as asked.
inline void enableVehicleAiding(EstimationProblem* p, bool odometer, bool nhc) {
  p->aiding.odometer.enabled = odometer;
  p->aiding.odometer.std_m_s << 0.05, 0.0, 0.0;
  p->aiding.odometer.scale_std = 0.01;
  p->aiding.nhc.enabled = nhc;
  p->aiding.nhc.std_m_s << 0.05, 0.05;
}

// RMS horizontal error over the solution's epochs inside the outage.
inline double outageHorizontalRms(const NavSolution& sol, const VehicleDrive& d) {
  double s = 0.0;
  int n = 0;
  const double t0 = d.truth.front().t_s;
  for (const NavState& st : sol.states) {
    if (!d.outage.contains(st.t_s)) continue;
    const auto k = static_cast<size_t>(std::llround((st.t_s - t0) * 100.0));  // truth at 100 Hz
    EXPECT_NEAR(st.t_s, d.truth.at(k).t_s, 1e-6);
    s += earth::nedFromGeodetic(d.truth[k].pos, st.pos).head<2>().squaredNorm();
    ++n;
  }
  EXPECT_GT(n, 5000);
  return std::sqrt(s / std::max(n, 1));
}

}  // namespace graftnav::test
