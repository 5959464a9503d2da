#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "graftnav/calibration/lab_data.h"
#include "graftnav/calibration/theoretical_output.h"
#include "graftnav/io/case_config.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

std::string fmtNum(double v, int prec = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", prec, v);
  return buf;
}

ImuSeries readLabImu(const std::string& path, double rate_hz) {
  ImuReadOptions ro;
  ro.nominal_rate_hz = rate_hz;
  ro.policy = ImuReadPolicy::real();
  return readImu(path, ro);
}

}  // namespace

void checkStaticPose(const StaticPose& pose, const ImuSeries& imu, double g,
                     const LabDataOptions& opt) {
  const double frac = staticFraction(imu, opt.pose_check);
  if (frac < opt.min_static_fraction)
    throw std::runtime_error(pose.file + ": pose '" + pose.name + "' is not static: only " +
                             fmtNum(100.0 * frac, 1) +
                             " % of the samples pass the static detector (need " +
                             fmtNum(100.0 * opt.min_static_fraction, 0) + " %)");
  const double w = pose.stats.omega_mean_rad_s.norm();
  if (w > opt.max_pose_rate_rad_s)
    throw std::runtime_error(pose.file + ": pose '" + pose.name + "' is not static: mean rate " +
                             fmtNum(w * kRadToDeg, 2) + " deg/s (limit " +
                             fmtNum(opt.max_pose_rate_rad_s * kRadToDeg, 2) + " deg/s)");
  const Eigen::Vector3d f_th = staticSpecificForce_b(pose.C_nb, g);
  const Eigen::Vector3d f = pose.stats.f_mean_m_s2;
  const double ang = std::atan2(f.cross(f_th).norm(), f.dot(f_th)) * kRadToDeg;
  if (!(ang <= opt.max_pose_angle_deg))
    throw std::runtime_error(pose.file + ": pose '" + pose.name + "': mean specific force [" +
                             fmtNum(f.x()) + ", " + fmtNum(f.y()) + ", " + fmtNum(f.z()) +
                             "] m/s^2 is " + fmtNum(ang, 1) +
                             " deg away from the attitude given for the pose (limit " +
                             fmtNum(opt.max_pose_angle_deg, 1) + " deg)");
}

namespace {

// The six-position poses: all six or none, each at the attitude case.yaml gives (or the default
// for its name), checked to be static and to point its axis up or down.
void loadSixPosition(const CasePaths& paths, const LabConfig& lab, const LabDataOptions& opt,
                     LabData& s) {
  namespace fs = std::filesystem;
  const std::string& case_dir = s.case_dir;
  int present = 0;
  for (int a = 0; a < 3; ++a)
    for (bool up : {true, false}) present += fs::exists(paths.sixPosition(a, up)) ? 1 : 0;
  if (present > 0) {
    for (int a = 0; a < 3; ++a)
      for (bool up : {true, false}) {
        const std::string file = paths.sixPosition(a, up);
        if (!fs::exists(file))
          throw std::runtime_error(file + ": missing six-position pose (found " +
                                   std::to_string(present) + " of 6 in " + case_dir +
                                   "/lab/six_position)");
        StaticPose p;
        p.name = std::string(1, char('x' + a)) + (up ? "_up" : "_down");
        p.file = file;
        const auto it = lab.six_position_euler_rad.find(p.name);
        const Eigen::Vector3d eul =
            it != lab.six_position_euler_rad.end() ? it->second : sixPositionDefaultEuler(p.name);
        p.C_nb = dcmFromEuler(eul);
        const Eigen::Vector3d up_b = p.C_nb.transpose() * Eigen::Vector3d(0, 0, -1);
        if (up_b[a] * (up ? 1.0 : -1.0) < std::cos(45.0 * kDegToRad))
          throw std::runtime_error(paths.caseYaml() + ": lab.six_position." + p.name +
                                   ": the attitude does not put the " +
                                   std::string(1, char('x' + a)) + " axis " + (up ? "up" : "down") +
                                   " (remember: x_up is pitch +90 deg in FRD/NED)");
        const ImuSeries imu = readLabImu(file, s.imu_rate_hz);
        p.stats = segmentStats(imu, file);
        checkStaticPose(p, imu, s.gravity_m_s2, opt);
        s.six_position.push_back(p);
      }
  }
}

}  // namespace

LabData loadLabData(const std::string& case_dir, const LabDataOptions& opt) {
  namespace fs = std::filesystem;
  const CasePaths paths(case_dir);
  LabData s;
  const CaseConfig cfg = loadCaseConfig(paths.caseYaml(), &s.warnings);
  if (!cfg.lab)
    throw std::runtime_error(paths.caseYaml() +
                             ": no lab: section (needed by the lab calibration)");
  const LabConfig& lab = *cfg.lab;
  s.case_dir = case_dir;
  s.name = cfg.name;
  s.imu_rate_hz = cfg.testedImuRateHz();
  s.lab.lat_rad = lab.latitude_rad;
  s.lab.h_m = lab.height_m;
  s.latitude_known =
      !(opt.treat_zero_latitude_as_unknown && lab.latitude_rad == 0.0 && lab.height_m == 0.0);
  if (opt.gravity_override_m_s2 > 0.0) {
    s.gravity_m_s2 = opt.gravity_override_m_s2;
    s.notes.push_back("gravity set by the user: " + fmtNum(s.gravity_m_s2, 5) + " m/s^2");
  } else if (s.latitude_known) {
    s.gravity_m_s2 = earth::gravityMagnitude(s.lab);
  } else {
    s.gravity_m_s2 = 9.80665;
    s.notes.push_back(
        "lab latitude/height unknown (0/0 placeholders in case.yaml): gravity 9.80665 m/s^2 "
        "(standard) and the Earth rate at latitude 0 are used");
  }
  if (lab.rate_table_axis_up && !*lab.rate_table_axis_up)
    throw std::runtime_error(paths.caseYaml() +
                             ": lab.rate_table.axis_up = false is not supported "
                             "(the turning axis must point up)");

  loadSixPosition(paths, lab, opt, s);
  for (const auto& [name, eul] : lab.tilt_euler_rad) {
    StaticPose p;
    p.name = name;
    p.file = paths.tilt(name);
    if (!fs::exists(p.file))
      throw std::runtime_error(p.file + ": missing tilt file named in case.yaml lab.tilt");
    p.C_nb = dcmFromEuler(eul);
    const ImuSeries imu = readLabImu(p.file, s.imu_rate_hz);
    p.stats = segmentStats(imu, p.file);
    checkStaticPose(p, imu, s.gravity_m_s2, opt);
    s.tilts.push_back(p);
  }
  for (const RateFile& rf : paths.rateFiles()) {
    const ImuSeries imu = readLabImu(rf.path, s.imu_rate_hz);
    RateRun r = makeRateRun(rf.path, rf.axis, rf.sign, rf.rate_deg_s, segmentStats(imu, rf.path));
    assignWholeTurns(r, opt.rate);
    s.rate_runs.push_back(r);
  }
  if (opt.load_static && fs::exists(paths.labStatic())) {
    s.static_file = paths.labStatic();
    s.static_imu = readLabImu(s.static_file, s.imu_rate_hz);
    s.static_C_nb = dcmFromEuler(lab.static_euler_rad.value_or(Eigen::Vector3d::Zero()));
    if (!lab.static_euler_rad)
      s.notes.push_back("lab.static.attitude_deg absent: level, yaw 0 assumed");
    StaticPose p;
    p.name = "static";
    p.file = s.static_file;
    p.C_nb = s.static_C_nb;
    p.stats = segmentStats(s.static_imu, s.static_file);
    checkStaticPose(p, s.static_imu, s.gravity_m_s2, opt);
    s.has_static = true;
  }
  if (s.six_position.empty() && !s.has_static)
    throw std::runtime_error(case_dir +
                             ": insufficient lab data: neither lab/six_position/*.txt nor "
                             "lab/static.txt exists");
  if (!s.rate_runs.empty() && s.six_position.empty() && !s.has_static)
    throw std::runtime_error(case_dir + ": rate runs need static data for the gyro bias");
  return s;
}

}  // namespace graftnav
