#pragma once
// The basic error signal of a tested IMU recorded in the field next to the reference (`graftnav
// real-sg`): no lab session exists, so its standstill spans stand in for the lab static record.
//
// Standstills are found by the static detector (calibration/static_detector.h) and kept only
// when the GNSS positions inside agree: a smooth constant-speed drive can pass the IMU variance
// test too. Over each kept span the error increments are the measured increments minus the
// theoretical output at rest: gravity of the normal magnitude along the span's own mean
// specific-force direction, and the Earth rate in the levelled body frame at the given heading.
// Levelling on the span's own mean absorbs the horizontal accelerometer bias into the tilt, as
// an alignment would.
#include <vector>

#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct StandstillOptions {
  StaticDetectorOptions detector = defaultDetector();
  // A detected span whose median GNSS speed (over chords of at least speed_chord_s between
  // fixes inside it) exceeds this is a slow drive, not a standstill. 0.3 m/s: well above the
  // chord speed that centimetre RTK noise fakes over 1 s, below a car creeping in traffic.
  double max_gnss_speed_m_s = 0.3;
  double speed_chord_s = 1.0;  // median of chord speeds: robust to single position blips
  // Throws std::invalid_argument naming the field.
  void validate() const;

  // The detector of real-sg: gyro <= 0.05 rad/s and accel <= 0.3 m/s^2 std over 1 s, spans of
  // at least 2 s with 0.5 s trimmed at each end (the vehicle settling).
  static StaticDetectorOptions defaultDetector();
};

struct StandstillSpans {
  StaticDetection detection;         // everything the detector found
  std::vector<StaticInterval> kept;  // the standstills (GNSS agrees)
  int dropped_moving = 0;            // detected spans dropped for their GNSS speed
};

// Median chord speed of the fixes inside [t_begin_s, t_end_s]; 0 when no chord fits.
double medianGnssChordSpeed(const GnssSeries& gnss, double t_begin_s, double t_end_s,
                            double chord_s);

// Standstill spans of `imu` confirmed by `gnss`. Throws std::runtime_error when none is left.
StandstillSpans findStandstills(const ImuSeries& imu, const GnssSeries& gnss,
                                const StandstillOptions& options);

// Error increments of `imu` over `spans`, concatenated on a time axis starting at 0 (the input of
// BasicErrorSignal). `pos` is where the vehicle stands, `yaw_rad` its heading.
ImuSeries staticErrorIncrements(const ImuSeries& imu, const std::vector<StaticInterval>& spans,
                                const Geodetic& pos, double yaw_rad);

}  // namespace graftnav
