#pragma once
// What every estimator (EKF, RTS, factor graph, free inertial) returns, and what it needs.
// Estimators live in filters/ and graph/; the app picks one by name and passes these structs.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "graftnav/estimation/gnss_source.h"
#include "graftnav/estimation/vehicle_aiding.h"
#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/time_window.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// 1-sigma uncertainty of one solution epoch: position north/east/down (m), velocity NED (m/s),
// attitude error about north/east/down (rad). NaN when the estimator gives none.
using PvaSigma = Eigen::Matrix<double, 9, 1>;

struct NavSolution {
  std::string estimator;        // "ekf", "rts", "fgo", "fgo-window", "free-inertial"
  NavSeries states;             // at the IMU rate (or a stated decimation)
  std::vector<PvaSigma> sigma;  // same length as states, or empty
  // Estimated IMU errors at each state epoch (same length as states, or empty):
  std::vector<Eigen::Vector3d> gyro_bias_rad_s, accel_bias_m_s2, gyro_scale, accel_scale;
  // Estimated odometer scale factor k (fraction) and its 1-sigma at each state epoch: same
  // length as states when the estimator estimates it (vehicle_aiding.h), else empty.
  std::vector<double> odometer_scale, odometer_scale_std;
  // GNSS bookkeeping.
  int gnss_used = 0;
  int gnss_rejected = 0;  // failed the innovation gate
  int gnss_withheld = 0;  // inside outages
  // Vehicle-frame velocity (odometer / NHC) updates or factors used and rejected by the gate.
  int vehicle_used = 0;
  int vehicle_rejected = 0;

  // Takes the estimator's name and the GNSS and vehicle bookkeeping of `from` (a streamed run's
  // result, which carries no series), leaving the series as they are.
  void copyBookkeeping(const NavSolution& from) {
    estimator = from.estimator;
    gnss_used = from.gnss_used;
    gnss_rejected = from.gnss_rejected;
    gnss_withheld = from.gnss_withheld;
    vehicle_used = from.vehicle_used;
    vehicle_rejected = from.vehicle_rejected;
  }
};

// The inputs shared by all estimators.
struct EstimationProblem {
  ImuSeries imu;
  GnssSeries gnss;                  // all epochs, in time order; the estimator withholds those
                                    // in outages
  GnssOpenFn gnss_stream;           // when set, the fixes come from here instead (gnss is not
                                    // read): memory not growing with the recording
  std::vector<TimeWindow> outages;  // GNSS withheld inside these
  NavState initial;                 // at (or just before) imu.front().t_s
  Eigen::Vector3d lever_arm_b_m = Eigen::Vector3d::Zero();  // antenna from IMU, body FRD
  ImuProfile imu_profile;  // noise and bias model of the IMU being navigated
  PvaSigma initial_sigma = PvaSigma::Constant(-1.0);  // < 0: estimator default
  // Odometer and NHC (off unless enabled); the odometer's samples come from odometer_stream when
  // set, else from `odometer` (in time order).
  VehicleAidingOptions aiding;
  OdometerSeries odometer;
  OdometerOpenFn odometer_stream;
  // A pass over the odometer samples (the stream when set, else the series).
  std::unique_ptr<OdometerSource> openOdometer() const;
};

// One pass over an IMU that need not be held in memory: calls `block` with consecutive blocks of
// samples in time order until the recording ends. Smoothers and factor graphs call it more than
// once.
using ImuBlockFn = std::function<void(const ImuSeries& block)>;
using ImuPassFn = std::function<void(const ImuBlockFn& block)>;

// Called by a long run with the fraction done (0..1), for progress lines.
using ProgressFn = std::function<void(double fraction_done)>;

}  // namespace graftnav
