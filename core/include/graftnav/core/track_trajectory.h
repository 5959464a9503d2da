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
//   m(t) = v_h^2 / (v_h^2 + v_osc^2).
// Every quantity has analytic derivatives, so omega_nb_b is exact.

#include <memory>
#include <string>
#include <vector>

#include "graftnav/core/trajectory.h"
#include "graftnav/core/types.h"

namespace graftnav {

// One road oscillation term added to an Euler angle: amplitude m(t) A sin(2 pi f (t - t0) + phase).
struct AttitudeOscillation {
  int euler_index = 0;       // 0 roll, 1 pitch, 2 yaw
  double amplitude_rad = 0.0;
  double frequency_hz = 1.0;
  double phase_rad = 0.0;
};

struct TrackSmoothingOptions {
  double position_cutoff_hz = 0.4;     // approximate -6 dB frequency of the position smoother
  double attitude_cutoff_hz = 0.3;     // same for the fitted Euler angles
  double knot_spacing_s = 1.0;         // P-spline knot spacing
  double outlier_sigma = 5.0;          // reject fixes farther than this many robust sigmas
  double stop_speed_m_s = 0.05;        // fitted speed below this is a stop...
  int stop_min_epochs = 5;             // ...when it lasts at least this many fixes
  double heading_hold_speed_m_s = 0.5; // hold yaw and pitch below this speed
  double roll_per_lateral_g_rad = 0.07;  // outward body roll per g of lateral acceleration (~4 deg/g)
  double lateral_speed_floor_m_s = 1.0;  // v_floor in a_lat
  double oscillation_speed_m_s = 2.0;    // v_osc in m(t)
  std::vector<AttitudeOscillation> oscillations = defaultOscillations();
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
  TrackFitReport report_;
};

}  // namespace graftnav
