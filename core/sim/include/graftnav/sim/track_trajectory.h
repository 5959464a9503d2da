#pragma once
// A truth trajectory built from a real GNSS track (1 Hz RTK positions, .pos).
//
// Position: each NED coordinate (in the tangent plane at the first fix) is a penalized quintic
// B-spline (P-spline: uniform knots, third-difference penalty), C4 in time, weighted by the
// inverse variance of the fix, with robust rejection of jumps and stops pinned to their mean.
// Attitude, relative to the local NED frame:
//   yaw   from the velocity direction, held through stops (speed < heading_hold_speed_m_s),
//   pitch from the climb angle atan2(-v_D, v_h), held through stops,
//   roll  = -roll_per_lateral_g_rad * a_lat / g0 (body rolls outward in a turn),
//         a_lat = (v_N a_E - v_E a_N) / sqrt(v_h^2 + v_floor^2) (smooth through stops),
// each sampled at 4 Hz from the position spline and fitted by its own quintic P-spline, plus
// small road oscillations (sinusoids) whose amplitude fades in with speed:
//   m(t) = v_h^2 / (v_h^2 + v_osc^2),
// and, optionally, road/engine vibration (RoadVibrationOptions, default off) as true motion:
// sinusoids in a band (8-40 Hz in cars) on the position, along the forward/right/down axes of the
// heading frame (yaw of the smoothed path), and on the Euler angles, faded in with speed by
//   m_vib(t) = v_h^2 / (v_h^2 + v_half^2).
// Every quantity has analytic derivatives, so omega_nb_b is exact.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/sim/trajectory.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// One road oscillation term added to an Euler angle: amplitude m(t) A sin(2 pi f (t - t0) + phase).
struct AttitudeOscillation {
  int euler_index = 0;  // 0 roll, 1 pitch, 2 yaw
  double amplitude_rad = 0.0;
  double frequency_hz = 1.0;
  double phase_rad = 0.0;
};

// One vibration sinusoid, m_vib(t) A sin(2 pi f (t - t0) + phase): a displacement (m) along axis
// 0 forward, 1 right, 2 down of the heading frame, or an Euler-angle term (rad) on 0 roll,
// 1 pitch, 2 yaw.
struct VibrationComponent {
  int axis = 0;
  double amplitude = 0.0;  // m (linear) or rad (angular)
  double frequency_hz = 10.0;
  double phase_rad = 0.0;
};

// Road/engine vibration of a body-mounted IMU in a car, as true motion. accel_rms_m_s2 is the rms
// of the vibration's specific-force VECTOR (sqrt of the summed per-axis mean squares; the
// vibration regressor is a squared norm too) at full amplitude (speed >> half_amplitude_speed);
// gyro_rms_rad_s the same for the angular rate. Mean-square shares per axis (fixed): linear
// forward 0.15, right 0.25, down 0.60; angular roll 0.40, pitch 0.45, yaw 0.15. `components`
// sinusoids each for the linear and the angular part, axis k % 3, frequencies uniform in
// [band_low_hz, band_high_hz] and phases uniform, drawn from `seed` (mt19937_64); the mean square
// of an axis is split equally over its sinusoids: acceleration amplitude sqrt(2 ms_i), so a
// displacement A = sqrt(2 ms_i) / (2 pi f)^2 (micrometres), an angle sqrt(2 ms_i) / (2 pi f).
struct RoadVibrationOptions {
  double accel_rms_m_s2 = 0.0;  // 0 and gyro_rms_rad_s 0: no vibration
  double gyro_rms_rad_s = 0.0;
  double band_low_hz = 8.0;
  double band_high_hz = 35.0;
  int components = 12;
  uint64_t seed = 1;
  double half_amplitude_speed_m_s = 5.0;  // v_half in m_vib
  bool enabled() const { return accel_rms_m_s2 > 0.0 || gyro_rms_rad_s > 0.0; }
  std::vector<VibrationComponent> linearComponents() const;   // displacement amplitudes (m)
  std::vector<VibrationComponent> angularComponents() const;  // angle amplitudes (rad)
  void validate() const;  // throws std::invalid_argument naming the field
};

struct TrackSmoothingOptions {
  double position_cutoff_hz = 0.4;      // approximate -6 dB frequency of the position smoother
  double attitude_cutoff_hz = 0.3;      // same for the fitted Euler angles
  double knot_spacing_s = 1.0;          // P-spline knot spacing
  double outlier_sigma = 5.0;           // reject fixes farther than this many robust sigmas
  double stop_speed_m_s = 0.05;         // fitted speed below this is a stop...
  int stop_min_epochs = 5;              // ...when it lasts at least this many fixes
  double heading_hold_speed_m_s = 0.5;  // hold yaw and pitch below this speed
  double roll_per_lateral_g_rad =
      0.07;  // outward body roll per g of lateral acceleration (~4 deg/g)
  double lateral_speed_floor_m_s = 1.0;  // v_floor in a_lat
  double oscillation_speed_m_s = 2.0;    // v_osc in m(t)
  std::vector<AttitudeOscillation> oscillations = defaultOscillations();
  RoadVibrationOptions vibration;  // default off
  static std::vector<AttitudeOscillation> defaultOscillations();
  void validate() const;  // throws std::invalid_argument naming the field
};

// Diagnostics of the fit (reported by `graftnav simulate`).
struct TrackFitReport {
  int fixes_used = 0;
  int fixes_rejected = 0;
  int stops = 0;
  double rms_residual_m[3] = {0, 0, 0};  // N, E, D
};

class TrackTrajectory final : public TangentPlaneTrajectory {
 public:
  // The fixes must be strictly increasing in time; at least 10 of them.
  TrackTrajectory(const GnssSeries& track, const TrackSmoothingOptions& opt = {});
  ~TrackTrajectory() override;
  TrackTrajectory(const TrackTrajectory&) = delete;
  TrackTrajectory& operator=(const TrackTrajectory&) = delete;

  double startTime_s() const override { return t_begin_; }
  double endTime_s() const override { return t_end_; }
  LocalKinematics local(double t_s) const override;
  const TrackFitReport& report() const { return report_; }

  class Spline;  // quintic P-spline, defined in the .cpp

 private:
  double t_begin_ = 0.0, t_end_ = 0.0;
  TrackSmoothingOptions opt_;
  std::unique_ptr<Spline> pos_[3];  // N, E, D in the tangent plane (m)
  std::unique_ptr<Spline> att_[3];  // roll, pitch, yaw (rad) without oscillations
  std::vector<VibrationComponent> vib_linear_, vib_angular_;  // drawn once from opt_.vibration
  void addVibration(double t_s, LocalKinematics& k) const;
  TrackFitReport report_;
};

}  // namespace graftnav
