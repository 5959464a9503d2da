#include "graftnav/sim/lab_simulator.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/sim/imu_simulator.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

const char* kAxisName[3] = {"x", "y", "z"};

long samplesFor(double duration_s, double rate_hz) {
  return static_cast<long>(std::llround(duration_s * rate_hz));
}

// Constant increments of a body at rest (exact: the integrand is constant).
ImuSeries staticSeries(const Geodetic& site, const Eigen::Vector3d& euler, double t0, double dur,
                       double rate_hz) {
  TrajectoryPoint p;
  p.pos = site;
  p.C_nb = dcmFromEuler(euler);
  const BodyRates r = bodyRates(p);
  const long n = samplesFor(dur, rate_hz);
  ImuSeries out(static_cast<std::size_t>(n));
  for (long k = 0; k < n; ++k) {
    ImuSample& s = out[static_cast<std::size_t>(k)];
    s.t_s = t0 + static_cast<double>(k + 1) / rate_hz;
    s.dt_s = 1.0 / rate_hz;
    s.dtheta_rad = r.omega_ib_b * s.dt_s;
    s.dvel_m_s = r.f_b * s.dt_s;
  }
  return out;
}

std::string rateLabel(double rate_deg_s) {
  char b[32];
  if (std::abs(rate_deg_s - std::round(rate_deg_s)) < 1e-9) {
    std::snprintf(b, sizeof b, "%.0f", rate_deg_s);
  } else {
    std::snprintf(b, sizeof b, "%g", rate_deg_s);
  }
  return b;
}

}  // namespace

void LabSimOptions::validate() const {
  auto fail = [](const std::string& key, double v, const std::string& why) {
    throw std::invalid_argument("LabSimOptions: " + key + " = " + std::to_string(v) + " " + why);
  };
  if (std::abs(latitude_rad) > units::kPi / 2) fail("latitude_rad", latitude_rad, "out of range");
  if (!(rate_hz > 0.0)) fail("rate_hz", rate_hz, "must be > 0");
  if (static_duration_s < 0.0) fail("static_duration_s", static_duration_s, "must be >= 0");
  if (six_position_duration_s < 0.0) {
    fail("six_position_duration_s", six_position_duration_s, "must be >= 0");
  }
  if (tilt_duration_s < 0.0) fail("tilt_duration_s", tilt_duration_s, "must be >= 0");
  if (!rate_table_rad_s.empty() && rate_table_turns < 1) {
    fail("rate_table_turns", rate_table_turns, "must be >= 1");
  }
  for (double w : rate_table_rad_s) {
    if (!(w > 0.0)) fail("rate_table rate (rad/s)", w, "must be > 0");
    const double n = rate_table_turns * 2.0 * units::kPi / w * rate_hz;
    if (std::abs(n - std::round(n)) > 1e-6) {
      fail("rate_table rate (deg/s)", w * units::kRadToDeg,
           "gives " + std::to_string(n) + " samples per " + std::to_string(rate_table_turns) +
               " turn(s) at " + std::to_string(rate_hz) + " Hz; whole turns need an integer");
    }
  }
}

std::map<std::string, Eigen::Vector3d> sixPositionPoses() {
  const double q = units::kPi / 2;
  return {{"x_up", {0, q, 0}},   {"x_down", {0, -q, 0}},       {"y_up", {-q, 0, 0}},
          {"y_down", {q, 0, 0}}, {"z_up", {units::kPi, 0, 0}}, {"z_down", {0, 0, 0}}};
}

LabTrajectory::LabTrajectory(const Geodetic& site, const Eigen::Matrix3d& C_nb0, int axis,
                             double rate_rad_s, double t0_s, double duration_s)
    : site_(site),
      C_nb0_(C_nb0),
      axis_(Eigen::Vector3d::Unit(axis)),
      rate_(rate_rad_s),
      t0_(t0_s),
      duration_(duration_s) {
  if (axis < 0 || axis > 2) {
    throw std::invalid_argument("LabTrajectory: axis must be 0..2, got " + std::to_string(axis));
  }
}

TrajectoryPoint LabTrajectory::at(double t_s) const {
  TrajectoryPoint p;
  p.t_s = t_s;
  p.pos = site_;
  p.C_nb = C_nb0_ * dcmFromRotationVector(axis_ * (rate_ * (t_s - t0_)));
  p.omega_nb_b = axis_ * rate_;
  return p;
}

std::vector<LabSession> simulateLabSessions(const LabSimOptions& opt) {
  opt.validate();
  const Geodetic site{opt.latitude_rad, opt.longitude_rad, opt.height_m};
  const double t0 = opt.start_time_s;
  std::vector<LabSession> out;
  if (opt.static_duration_s > 0.0) {
    out.push_back({"lab/static.txt", staticSeries(site, opt.static_euler_rad, t0,
                                                  opt.static_duration_s, opt.rate_hz)});
  }
  const auto poses = sixPositionPoses();
  if (opt.six_position_duration_s > 0.0) {
    for (const auto& [name, e] : poses) {
      out.push_back({"lab/six_position/" + name + ".txt",
                     staticSeries(site, e, t0, opt.six_position_duration_s, opt.rate_hz)});
    }
  }
  IdealImuOptions io;
  io.rate_hz = opt.rate_hz;
  io.quadrature_nodes = opt.quadrature_nodes;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Matrix3d C0 = dcmFromEuler(poses.at(std::string(kAxisName[axis]) + "_up"));
    for (int sign : {1, -1}) {
      for (double w : opt.rate_table_rad_s) {
        const double dur = opt.rate_table_turns * 2.0 * units::kPi / w;
        const LabTrajectory trj(site, C0, axis, sign * w, t0, dur);
        // Sample count from the exact duration (validated to be an integer).
        const double t_end = t0 + static_cast<double>(samplesFor(dur, opt.rate_hz)) / opt.rate_hz;
        out.push_back({std::string("lab/rate/") + kAxisName[axis] + (sign > 0 ? "_pos_" : "_neg_") +
                           rateLabel(w * units::kRadToDeg) + ".txt",
                       simulateIdealImu(trj, t0, t_end, io)});
      }
    }
  }
  if (opt.tilt_duration_s > 0.0) {
    for (const auto& [name, e] : opt.tilt_euler_rad) {
      out.push_back({"lab/tilt/" + name + ".txt",
                     staticSeries(site, e, t0, opt.tilt_duration_s, opt.rate_hz)});
    }
  }
  return out;
}

}  // namespace graftnav
