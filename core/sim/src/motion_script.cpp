#include "graftnav/sim/motion_script.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/sim/imu_simulator.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

// Smootherstep S(x) (C3, S(0)=0, S(1)=1, S' = 140 x^3 (1-x)^3) and its integral I(x), I(1) = 1/2.
double S(double x) { return x * x * x * x * (35.0 + x * (-84.0 + x * (70.0 - 20.0 * x))); }
double dS(double x) { return 140.0 * x * x * x * (1.0 - x) * (1.0 - x) * (1.0 - x); }
double I(double x) { return x * x * x * x * x * (7.0 + x * (-14.0 + x * (10.0 - 2.5 * x))); }

struct PieceState {
  double speed, dspeed, yaw, rate, drate;
};

PieceState evalPiece(const ScriptTrajectory::Piece& p, double tau) {
  tau = std::clamp(tau, 0.0, p.duration_s);
  PieceState s{};
  const double T = p.duration_s;
  const double x = T > 0.0 ? tau / T : 0.0;
  s.speed = p.speed0_m_s + (p.speed1_m_s - p.speed0_m_s) * S(x);
  s.dspeed = T > 0.0 ? (p.speed1_m_s - p.speed0_m_s) * dS(x) / T : 0.0;
  const double r = p.rate_rad_s, Tr = p.ramp_s;
  s.yaw = p.yaw0_rad;
  if (r != 0.0) {
    if (tau < Tr) {
      s.rate = r * S(tau / Tr);
      s.drate = r * dS(tau / Tr) / Tr;
      s.yaw += r * Tr * I(tau / Tr);
    } else if (tau <= T - Tr) {
      s.rate = r;
      s.yaw += r * Tr * 0.5 + r * (tau - Tr);
    } else {
      const double y = (T - tau) / Tr;
      s.rate = r * S(y);
      s.drate = -r * dS(y) / Tr;
      s.yaw += r * Tr * 0.5 + r * (T - 2.0 * Tr) + r * Tr * (0.5 - I(y));
    }
  }
  return s;
}

Eigen::Vector3d velocity(const PieceState& s) {
  return {s.speed * std::cos(s.yaw), s.speed * std::sin(s.yaw), 0.0};
}

const GaussLegendreRule& rule8() {
  static const GaussLegendreRule r = gaussLegendreRule(8);
  return r;
}

Eigen::Vector3d integrateVelocity(const ScriptTrajectory::Piece& p, double a, double b) {
  const double h = 0.5 * (b - a), m = 0.5 * (a + b);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < rule8().nodes.size(); ++i) {
    sum += rule8().weights[i] * velocity(evalPiece(p, m + h * rule8().nodes[i]));
  }
  return h * sum;
}

}  // namespace

MotionSegment::Type motionSegmentType(const std::string& n) {
  if (n == "static") return MotionSegment::Type::kStatic;
  if (n == "accelerate") return MotionSegment::Type::kAccelerate;
  if (n == "cruise") return MotionSegment::Type::kCruise;
  if (n == "turn") return MotionSegment::Type::kTurn;
  if (n == "stop") return MotionSegment::Type::kStop;
  if (n == "figure_eight") return MotionSegment::Type::kFigureEight;
  throw std::invalid_argument("motion script: unknown segment type '" + n +
                              "' (static, accelerate, cruise, turn, stop, figure_eight)");
}

void MotionScript::validate() const {
  if (segments.empty()) throw std::invalid_argument("motion script: no segments");
  if (!(ramp_s > 0.0)) {
    throw std::invalid_argument("motion script: ramp_s must be > 0, got " + std::to_string(ramp_s));
  }
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto& s = segments[i];
    const std::string where = "motion script: segment " + std::to_string(i + 1) + ": ";
    if (s.type == MotionSegment::Type::kFigureEight) {
      if (!(s.radius_m > 0.0)) {
        throw std::invalid_argument(where + "radius_m must be > 0, got " +
                                    std::to_string(s.radius_m));
      }
      if (s.laps < 1) {
        throw std::invalid_argument(where + "laps must be >= 1, got " + std::to_string(s.laps));
      }
    } else if (!(s.duration_s > 0.0)) {
      throw std::invalid_argument(where + "duration_s must be > 0, got " +
                                  std::to_string(s.duration_s));
    }
    if (s.type == MotionSegment::Type::kAccelerate && !(s.to_speed_m_s >= 0.0)) {
      throw std::invalid_argument(where + "to_speed_m_s must be >= 0, got " +
                                  std::to_string(s.to_speed_m_s));
    }
  }
}

ScriptTrajectory::ScriptTrajectory(const MotionScript& script)
    : TangentPlaneTrajectory(script.start), roll_k_(script.roll_per_lateral_g_rad) {
  script.validate();
  t_begin_ = script.start_time_s;
  double t = t_begin_, speed = 0.0, yaw = script.initial_yaw_rad;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  auto push = [&](Piece pc) {
    pc.t0_s = t;
    pc.speed0_m_s = speed;
    pc.yaw0_rad = yaw;
    pc.p0_n0 = p;
    if (pc.rate_rad_s != 0.0) pc.ramp_s = std::min(script.ramp_s, 0.25 * pc.duration_s);
    const int ncell = std::max(1, static_cast<int>(std::ceil(pc.duration_s / 0.1 - 1e-9)));
    pc.grid_dt_s = pc.duration_s / ncell;
    pc.grid_p_n0.resize(ncell + 1);
    pc.grid_p_n0[0] = p;
    for (int i = 0; i < ncell; ++i) {
      pc.grid_p_n0[i + 1] =
          pc.grid_p_n0[i] + integrateVelocity(pc, i * pc.grid_dt_s, (i + 1) * pc.grid_dt_s);
    }
    const PieceState end = evalPiece(pc, pc.duration_s);
    t += pc.duration_s;
    speed = end.speed;
    yaw = end.yaw;
    p = pc.grid_p_n0.back();
    pieces_.push_back(std::move(pc));
  };
  for (std::size_t i = 0; i < script.segments.size(); ++i) {
    const MotionSegment& s = script.segments[i];
    Piece pc;
    pc.duration_s = s.duration_s;
    pc.speed1_m_s = speed;
    switch (s.type) {
      case MotionSegment::Type::kStatic:
        if (speed != 0.0) {
          throw std::invalid_argument("motion script: segment " + std::to_string(i + 1) +
                                      ": static while moving at " + std::to_string(speed) +
                                      " m/s (add a stop first)");
        }
        push(pc);
        break;
      case MotionSegment::Type::kAccelerate:
        pc.speed1_m_s = s.to_speed_m_s;
        push(pc);
        break;
      case MotionSegment::Type::kStop:
        pc.speed1_m_s = 0.0;
        push(pc);
        break;
      case MotionSegment::Type::kCruise:
        push(pc);
        break;
      case MotionSegment::Type::kTurn:
        pc.rate_rad_s = s.rate_rad_s;
        push(pc);
        break;
      case MotionSegment::Type::kFigureEight: {
        if (!(speed > 0.0)) {
          throw std::invalid_argument("motion script: segment " + std::to_string(i + 1) +
                                      ": figure_eight needs a speed > 0 (accelerate first)");
        }
        const double r = speed / s.radius_m;
        // Each loop turns exactly 360 deg: the two ramps lose r * ramp in total.
        const double ramp = script.ramp_s;
        const double T = 2.0 * units::kPi / r + ramp;
        if (ramp > 0.25 * T) {
          throw std::invalid_argument("motion script: segment " + std::to_string(i + 1) +
                                      ": figure_eight loop too short for ramp_s");
        }
        for (int lap = 0; lap < s.laps; ++lap) {
          for (int sign : {1, -1}) {
            Piece q;
            q.duration_s = T;
            q.speed1_m_s = speed;
            q.rate_rad_s = sign * r;
            push(q);
          }
        }
        break;
      }
    }
  }
  t_end_ = t;
}

TangentPlaneTrajectory::LocalKinematics ScriptTrajectory::local(double t_s) const {
  // Last piece starting at or before t.
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t_s,
                             [](double t, const Piece& p) { return t < p.t0_s; });
  const Piece& pc = (it == pieces_.begin()) ? pieces_.front() : *(it - 1);
  const double tau = std::clamp(t_s - pc.t0_s, 0.0, pc.duration_s);
  const PieceState s = evalPiece(pc, tau);
  const int cell = std::clamp(static_cast<int>(std::floor(tau / pc.grid_dt_s)), 0,
                              static_cast<int>(pc.grid_p_n0.size()) - 2);
  LocalKinematics k;
  k.p_n0 = pc.grid_p_n0[cell] + integrateVelocity(pc, cell * pc.grid_dt_s, tau);
  k.v_n0 = velocity(s);
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  k.a_n0 = Eigen::Vector3d(s.dspeed * c - s.speed * s.rate * sn,
                           s.dspeed * sn + s.speed * s.rate * c, 0.0);
  const double g0 = units::kStandardGravity_m_s2;
  k.euler_rad = {-roll_k_ * s.speed * s.rate / g0, 0.0, s.yaw};
  k.euler_rate_rad_s = {-roll_k_ * (s.dspeed * s.rate + s.speed * s.drate) / g0, 0.0, s.rate};
  return k;
}

}  // namespace graftnav
