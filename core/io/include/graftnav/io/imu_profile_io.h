#pragma once
// IMU profile files (configs/imu/*.yaml) and the IMU sections of case.yaml, in the seed's Table 1
// units with unit-named keys. This is the only place where these units are converted to the SI
// fields of ImuProfile.
//
//   name: POS1100-like                     # optional (default: file stem)
//   grade: mems                            # navigation | tactical | mems
//   gyro_bias_instability_deg_h: 10        # 1-sigma Gauss-Markov bias instability
//   arw_deg_rt_h: 0.15                     # angle random walk, deg/sqrt(h)
//   gyro_scale_ppm: 1000                   # optional, scale-factor 1-sigma
//   accel_bias_instability_mg: 1.0
//   vrw_m_s_rt_h: 0.06                     # velocity random walk, m/s/sqrt(h)
//   accel_scale_ppm: 1000                  # optional
//   correlation_time_s: 3600               # optional: Gauss-Markov time of biases and scales
//   gyro_bias_correlation_time_s / accel_bias_correlation_time_s / scale_correlation_time_s:
//                                          # optional overrides of correlation_time_s
//   gyro_bias_initial_deg_h / accel_bias_initial_mg: optional turn-on bias 1-sigma
//                                          # (default: the bias instability)
//   plausible_ranges:                      # optional (graftnav/imu/plausible_ranges.h)
//     sensor_class: consumer_mems          # default from grade: mems -> consumer_mems
//     source: "..."                        # optional: where overridden bounds come from
//     gyro_scale_max_ppm / accel_scale_max_ppm, gyro_nonorthogonality_max_deg /
//     accel_nonorthogonality_max_deg, gyro_scale_asymmetry_max_ppm / accel_..._ppm,
//     gyro_scale_nonlinearity_max_per_rad_s, accel_scale_nonlinearity_max_per_m_s2,
//     g_sensitivity_max_deg_h_per_g        # each optional, > 0: overrides the class's bound

#include <string>
#include <vector>

#include "graftnav/imu/imu_profile.h"

namespace YAML {
class Node;
class Emitter;
}  // namespace YAML

namespace graftnav {

// Loads a profile file. The four noise keys are required. Unknown keys are appended to *warnings
// ("path:line: unknown key 'x' ignored"). Throws std::runtime_error naming file, line and key for a
// missing file, a missing key, a wrong type or a negative value.
ImuProfile loadImuProfile(const std::string& path, std::vector<std::string>* warnings = nullptr);

// Writes a profile file atomically (same keys; SI converted back to Table 1 units).
void saveImuProfile(const std::string& path, const ImuProfile& profile);

// --- used by the case.yaml parser and writer ---
struct ImuProfileParse {
  ImuProfile profile;
  bool noise_given =
      false;  // the four noise keys were present (else the noise fields are 0 = unknown)
};
// Parses one profile map. key_prefix names it in messages ("tested_imu"); require_noise makes
// the four noise keys required (profile files), otherwise they are optional as a group (all four
// or none). file_path is used in messages only.
ImuProfileParse parseImuProfileNode(const YAML::Node& node, const std::string& file_path,
                                    const std::string& key_prefix, bool require_noise,
                                    std::vector<std::string>* warnings);
// Emits the profile as a YAML map; with_noise = false writes only name and grade.
void emitImuProfile(YAML::Emitter& out, const ImuProfile& profile, bool with_noise);

}  // namespace graftnav
