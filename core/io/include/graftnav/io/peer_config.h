#pragma once
// The set-up files of the two i2Nav GNSS/INS programs, KF-GINS (an EKF) and OB_GINS (a sliding-
// window optimizer), parsed into one typed description in SI units. Both read the same i2Nav text
// files graftnav reads (IMU increments, GNSS .pos), so only the configuration needs converting.
//
// KF-GINS keys (its published kf-gins.yaml) and their units:
//   imupath, gnsspath, outputpath, imudatalen, imudatarate (Hz), starttime, endtime (s of week,
//   -1 = to the end), initpos [lat deg, lon deg, h m], initvel [N E D m/s], initatt [roll pitch
//   yaw deg], initgyrbias (deg/h), initaccbias (mGal), initgyrscale / initaccscale (ppm),
//   initposstd (m, NED), initvelstd (m/s), initattstd (deg), optional initbgstd (deg/h),
//   initbastd (mGal), initsgstd / initsastd (ppm), imunoise: {arw deg/sqrt(h), vrw m/s/sqrt(h),
//   gbstd deg/h, abstd mGal, gsstd / asstd ppm, corrtime h}, antlever [m, body FRD].
// OB_GINS keys (its published ob_gins.yaml):
//   imufile, gnssfile, outputpath, windows, starttime, endtime, initvel, initatt, initgb (deg/h),
//   initab (mGal), imudatalen, imudatarate, isearth, antlever, odolever, bodyangle,
//   odometer: {isuseodo, std, srw}, imumodel: {arw, vrw, gbstd, abstd, corrtime} (units as above),
//   isuseoutage, outagetime, outagelen, outageperiod (s), gnssthreshold (m). odolever (m, FRD),
//   bodyangle (deg, roll pitch yaw of the IMU in the vehicle), odometer.std (m/s/sqrt(Hz), forward
//   lateral vertical), odometer.srw (ppm/sqrt(s), the random-walk density of its scale state).
// Anything that has no graftnav counterpart, or was interpreted, is recorded in PeerSetup::notes.

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/types.h"

namespace graftnav {

enum class PeerFormat { kKfGins, kObGins };

// "kf-gins" / "ob-gins" -> format; throws std::invalid_argument naming the text otherwise.
PeerFormat peerFormatFromName(const std::string& name);
std::string peerFormatName(PeerFormat format);

// OB_GINS's odometer set-up, in SI: `odometer: {isuseodo, std, srw}`, `odolever`, `bodyangle`.
// Its IMU file carries the odometer speed (m/s, mean over the sample) in column 8, or in
// columns 8 and 9 (two wheels, averaged) with imudatalen 9.
struct PeerOdometer {
  bool enabled = false;  // isuseodo
  // OB_GINS's std (forward, lateral, vertical) is a noise density: its preintegration grows the
  // variance of the odometer displacement by std^2 dt. As graftnav's 1-sigma of one update at
  // rate_hz (the mean speed over 1 / rate_hz): std * sqrt(rate_hz).
  double rate_hz = 10.0;
  Eigen::Vector3d std_m_s = Eigen::Vector3d(0.05, 0.05, 0.05) * std::sqrt(10.0);
  std::optional<double> scale_random_walk_per_sqrt_s;      // srw (ppm -> fraction, per sqrt(s))
  Eigen::Vector3d lever_arm_m = Eigen::Vector3d::Zero();   // odolever, from the IMU, FRD
  Eigen::Vector3d mounting_rad = Eigen::Vector3d::Zero();  // bodyangle: IMU in the vehicle
};

// A periodic outage schedule in absolute seconds of week (OB_GINS isuseoutage).
struct PeerOutageSchedule {
  double first_start_s = 0.0;
  double length_s = 60.0;
  double period_s = 180.0;
};

struct PeerSetup {
  PeerFormat format = PeerFormat::kKfGins;
  std::string config_path;      // the peer's yaml, as given
  std::string imu_path;         // resolved (exists)
  std::string gnss_path;        // resolved (exists)
  int imu_columns = 7;          // imudatalen
  double imu_rate_hz = 0.0;     // imudatarate
  double start_s = 0.0;         // starttime
  std::optional<double> end_s;  // endtime; nullopt = to the end of the IMU file
  // Initial position: KF-GINS initpos; OB_GINS has none (the importer takes the first GNSS fix).
  std::optional<Geodetic> initial_position;
  Eigen::Vector3d initial_velocity_ned_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d initial_euler_rad = Eigen::Vector3d::Zero();  // roll, pitch, yaw
  // Initial 1-sigma of the filter (KF-GINS initposstd, initvelstd, initattstd); nullopt: not given.
  std::optional<Eigen::Vector3d> initial_pos_std_m, initial_vel_std_m_s, initial_att_std_rad;
  ImuProfile profile;                          // noise converted to SI; name "<format> imunoise"
  std::optional<Eigen::Vector3d> lever_arm_m;  // antlever, antenna from the IMU, body FRD
  std::optional<PeerOutageSchedule> outage_schedule;  // OB_GINS isuseoutage: true
  std::optional<double> gnss_max_std_m;               // OB_GINS gnssthreshold
  std::optional<int> window_nodes;                    // OB_GINS windows
  std::optional<bool> earth_rotation;                 // OB_GINS isearth
  std::optional<PeerOdometer> odometer;               // OB_GINS odometer keys, when present
  // IMU columns after the 7th that hold the odometer speed (OB_GINS imudatalen 8 or 9: 1 or 2;
  // 0: none). Never read as a temperature.
  int odometer_columns = 0;
  std::vector<std::string> notes;  // what was assumed, interpreted or not converted
};

// Reads a peer's yaml. Relative data paths are tried against the yaml's folder, then against the
// current folder; the error names every path tried. Unknown keys are appended to *warnings.
// Throws std::runtime_error naming file, line and key for a missing key or a wrong value.
PeerSetup loadPeerConfig(PeerFormat format, const std::string& path,
                         std::vector<std::string>* warnings = nullptr);

}  // namespace graftnav
