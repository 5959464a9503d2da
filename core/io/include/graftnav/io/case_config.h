#pragma once
// case.yaml (dataset.md) as a typed struct, its parser and writer, and the standard file paths of
// a case directory. Angles are stored in radians (the file holds degrees); IMU sections are parsed
// by imu_profile_io.h (Table 1 units -> SI).

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/types.h"

namespace YAML {
class Node;
}  // namespace YAML

namespace graftnav {

struct LabConfig {
  double latitude_rad = 0.0;  // lab.latitude_deg (required in a lab section)
  double height_m = 0.0;      // lab.height_m (required in a lab section)
  // lab.static.attitude_deg: [roll, pitch, yaw] of the tested IMU during lab/static.txt.
  std::optional<Eigen::Vector3d> static_euler_rad;
  // lab.six_position: pose name (x_up, x_down, y_up, y_down, z_up, z_down) -> [roll, pitch, yaw].
  // Empty when the section is absent (then each pose is the one named by its file, yaw 0).
  std::map<std::string, Eigen::Vector3d> six_position_euler_rad;
  // lab.rate_table.axis_up: during rate tests the turning axis points up. Absent -> nullopt.
  std::optional<bool> rate_table_axis_up;
  // lab.tilt: name -> [roll, pitch, yaw] of lab/tilt/<name>.txt.
  std::map<std::string, Eigen::Vector3d> tilt_euler_rad;
};

struct CaseConfig {
  std::string name;          // required
  double imu_rate_hz = 0.0;  // required, > 0 (reference IMU, and tested IMU unless...)
  std::optional<double> tested_imu_rate_hz;  // ...this is given
  std::optional<std::string>
      reference_solution;  // path relative to the case dir, e.g. field/reference.nav
  // IMU sections. A section may hold only the grade ({grade: mems}); then *_noise_given is false and
  // the noise fields are 0, meaning UNKNOWN (not perfect).
  std::optional<ImuProfile> reference_imu;
  bool reference_imu_noise_given = false;
  std::optional<ImuProfile> tested_imu;
  bool tested_imu_noise_given = false;
  std::optional<Eigen::Vector3d>
      lever_arm_m;               // antenna phase centre from the reference IMU, FRD (m)
  std::optional<int> gnss_week;  // gnss.week
  // initial_state: time, position (deg, deg, m), velocity_ned, attitude_deg; gnss_week from gnss.week.
  std::optional<NavState> initial_state;
  std::optional<LabConfig> lab;

  double testedImuRateHz() const { return tested_imu_rate_hz.value_or(imu_rate_hz); }
};

// Parses case.yaml. Unknown keys are appended to *warnings ("path:line: unknown key 'a.b' ignored").
// Throws std::runtime_error naming the file, line and key for a missing file, a YAML syntax error,
// a missing required key, a wrong type or an invalid value.
CaseConfig loadCaseConfig(const std::string& path, std::vector<std::string>* warnings = nullptr);
// The same from a YAML node (a case built in memory, the Python module's Case.from_arrays);
// `source` names it in messages.
CaseConfig parseCaseConfig(const YAML::Node& root, const std::string& source,
                           std::vector<std::string>* warnings = nullptr);

// Writes case.yaml atomically (degrees in the file, 15 significant digits). Throws
// std::invalid_argument when the config would not load back (empty name, rate <= 0, ...).
void saveCaseConfig(const std::string& path, const CaseConfig& config);

// A rate-table file lab/rate/<x|y|z>_<pos|neg>_<deg/s>.txt with its parsed name.
struct RateFile {
  std::string path;
  int axis = 0;               // 0 x, 1 y, 2 z (body FRD)
  int sign = 1;               // +1 pos (right-handed positive rotation about the axis), -1 neg
  double rate_deg_s = 0.0;    // the number in the file name (deg/s, > 0)
  double rate_rad_s() const;  // sign * rate in rad/s
};

// Standard paths of a case directory (dataset.md). Nothing is checked for existence here.
class CasePaths {
 public:
  explicit CasePaths(std::string case_dir);
  const std::string& dir() const { return dir_; }
  std::string caseYaml() const;
  std::string refImu() const;       // field/ref_imu.txt
  std::string testedImu() const;    // field/tested_imu.txt
  std::string gnssPos() const;      // field/gnss.pos
  std::string gnssFixType() const;  // field/gnss_fixtype.txt
  std::string truthNav() const;     // field/truth.nav
  std::string odometer() const;     // field/odometer.txt
  // The external reference solution named by case.yaml (nullopt when the key is absent).
  std::optional<std::string> referenceSolution(const CaseConfig& config) const;
  std::string labStatic() const;  // lab/static.txt
  // lab/six_position/<x|y|z>_<up|down>.txt; axis 0..2. Throws std::invalid_argument otherwise.
  std::string sixPosition(int axis, bool up) const;
  std::string rateDir() const;                      // lab/rate
  std::string tilt(const std::string& name) const;  // lab/tilt/<name>.txt
  // Lists lab/rate/*.txt sorted by (axis, sign, rate); empty when the folder does not exist.
  // Throws std::runtime_error naming the file when a .txt name does not follow the pattern.
  std::vector<RateFile> rateFiles() const;

  static bool exists(const std::string& path);

 private:
  std::string dir_;
};

// Parses a rate file name ("z_neg_30.txt" -> axis 2, sign -1, 30 deg/s); nullopt when it does not
// match <x|y|z>_<pos|neg>_<positive number>.txt.
std::optional<RateFile> parseRateFileName(const std::string& file_name);

}  // namespace graftnav
