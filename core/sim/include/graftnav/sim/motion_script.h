#pragma once
// A truth trajectory from a motion script: a list of segments (static, accelerate, cruise, turn,
// stop, figure-eight) driven on a flat tangent plane (local level at the start point).
//
// Profiles are smooth: speed changes follow the C3 "smootherstep" S(x) = 35x^4 - 84x^5 + 70x^6 -
// 20x^7 over the whole segment; a turn's yaw rate ramps up and down with S over ramp_s at each
// end, so the commanded rate holds exactly on the plateau. Yaw and speed are analytic; the
// position is the integral of the velocity, by 8-point Gauss-Legendre on a 0.1 s grid (exact to
// rounding for these smooth profiles). Attitude: yaw from the script, pitch 0, roll outward in
// turns, roll = -roll_per_lateral_g_rad * a_lat / g0 with a_lat = speed * yaw rate.

#include <string>
#include <vector>

#include "graftnav/sim/trajectory.h"

namespace graftnav {

struct MotionSegment {
  enum class Type { kStatic, kAccelerate, kCruise, kTurn, kStop, kFigureEight };
  Type type = Type::kStatic;
  double duration_s = 0.0;    // static, accelerate, cruise, turn, stop
  double to_speed_m_s = 0.0;  // accelerate: speed at the end
  double rate_rad_s = 0.0;    // turn: yaw rate on the plateau (positive = right turn)
  double radius_m = 0.0;      // figure_eight: radius of each loop (at the current speed)
  int laps = 1;               // figure_eight: number of eights
};
// "static" | "accelerate" | "cruise" | "turn" | "stop" | "figure_eight" (throws otherwise).
MotionSegment::Type motionSegmentType(const std::string& name);

struct MotionScript {
  double start_time_s = 0.0;  // GNSS seconds of week
  Geodetic start;
  double initial_yaw_rad = 0.0;
  double ramp_s = 1.0;                   // yaw-rate ramp length at each end of a turn
  double roll_per_lateral_g_rad = 0.07;  // outward roll per g of lateral acceleration
  std::vector<MotionSegment> segments;
  void validate() const;  // throws std::invalid_argument naming the segment and field
};

class ScriptTrajectory final : public TangentPlaneTrajectory {
 public:
  explicit ScriptTrajectory(const MotionScript& script);
  double startTime_s() const override { return t_begin_; }
  double endTime_s() const override { return t_end_; }
  LocalKinematics local(double t_s) const override;

  // One expanded piece (figure-eights become turns); public for tests and docs.
  struct Piece {
    double t0_s = 0.0, duration_s = 0.0;
    double speed0_m_s = 0.0, speed1_m_s = 0.0;  // smootherstep between them
    double rate_rad_s = 0.0, ramp_s = 0.0;      // yaw-rate plateau and ramps
    double yaw0_rad = 0.0;
    Eigen::Vector3d p0_n0 = Eigen::Vector3d::Zero();
    double grid_dt_s = 0.1;
    std::vector<Eigen::Vector3d> grid_p_n0;  // position at t0 + i grid_dt
  };
  const std::vector<Piece>& pieces() const { return pieces_; }

 private:
  double t_begin_ = 0.0, t_end_ = 0.0;
  double roll_k_ = 0.0;
  std::vector<Piece> pieces_;
};

}  // namespace graftnav
