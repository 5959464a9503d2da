#pragma once
// Loads the lab part of a case directory (dataset.md: lab/static.txt, lab/six_position/*.txt,
// lab/rate/*.txt, lab/tilt/*.txt, case.yaml lab:) into the inputs of the lab estimators, and
// rejects bad or insufficient lab data with an error naming the file:
//  - a six-position set with a missing pose (all six or none);
//  - a pose that is not static (fewer than min_static_fraction of its samples pass the variance
//    detector, or a mean rate above max_pose_rate_rad_s) or whose mean specific force points more than max_pose_angle_deg away from the
//    attitude it is said to have (case.yaml lab.six_position / lab.tilt, or the default of its
//    name, see six_position.h);
//  - a rate file that does not hold whole turns, or rate_table.axis_up false (not supported);
//  - no usable lab data at all.
// Latitude: case.yaml lab.latitude_deg and height_m both 0 is the data set's "UNKNOWN"
// placeholder (see shared/data/real/README.md); then gravity 9.80665 m/s^2 is used, the Earth
// rate is taken at latitude 0, and a note says so.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "graftnav/calibration/gyro_calibration.h"
#include "graftnav/calibration/six_position.h"
#include "graftnav/calibration/static_detector.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct LabDataOptions {
  StaticDetectorOptions pose_check = defaultPoseCheck();
  double min_static_fraction = 0.8;
  double max_pose_angle_deg = 20.0;
  // A constant-rate turn has no variance: a pose whose mean rate exceeds this is not static
  // (5.7 deg/s; MEMS gyro biases are below ~1 deg/s).
  double max_pose_rate_rad_s = 0.1;
  double gravity_override_m_s2 = 0.0;  // > 0: use this gravity magnitude
  bool treat_zero_latitude_as_unknown = true;
  bool load_static = true;
  RateRunOptions rate;
  static StaticDetectorOptions defaultPoseCheck() {
    StaticDetectorOptions o;
    o.window_s = 0.5;
    o.gyro_threshold_rad_s = 0.1;  // 5.7 deg/s: hand-held poses still pass, motion does not
    o.accel_threshold_m_s2 = 0.5;
    o.min_duration_s = 0.0;
    return o;
  }
};

struct LabData {
  std::string case_dir;
  std::string name;
  double imu_rate_hz = 0.0;
  Geodetic lab;
  bool latitude_known = true;
  double gravity_m_s2 = 0.0;
  std::vector<StaticPose> six_position;  // x_up, x_down, y_up, y_down, z_up, z_down or empty
  std::vector<StaticPose> tilts;
  std::vector<RateRun> rate_runs;
  bool has_static = false;
  std::string static_file;
  ImuSeries static_imu;
  Eigen::Matrix3d static_C_nb = Eigen::Matrix3d::Identity();
  std::vector<std::string> notes;     // non-fatal remarks for the report
  std::vector<std::string> warnings;  // case.yaml's reader: unknown keys ("path:line: ...")
  // Length of the static record (first sample's start to last sample's end); 0 without one.
  double staticRecordSeconds() const {
    return static_imu.empty()
               ? 0.0
               : static_imu.back().t_s - static_imu.front().t_s + static_imu.front().dt_s;
  }
};

// Throws std::runtime_error naming the file (and the reason) for the conditions listed above;
// case.yaml's unknown keys go to LabData::warnings.
LabData loadLabData(const std::string& case_dir, const LabDataOptions& options = {});

// Checks one static pose (staticFraction and attitude consistency); throws std::runtime_error
// naming pose.file. Exposed for tests.
void checkStaticPose(const StaticPose& pose, const ImuSeries& imu, double gravity_m_s2,
                     const LabDataOptions& options);

}  // namespace graftnav
