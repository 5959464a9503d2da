#pragma once
// The simulator's configuration (configs/sim/*.yaml), parsed in one place into typed structs.
// Units in the file are named by the keys (deg, deg/h, mg, ppm, urad); the structs are SI.
// Relative paths in the file are resolved against the directory of the config file.
//
//   name: tactical_57min            # case name written to case.yaml
//   seed: 1                         # default seed (--seed overrides)
//   gnss_week: 2100
//   imu_rate_hz: 200
//   quadrature_nodes: 6
//   truth_rate_hz: 200              # truth.nav rate (a divisor of imu_rate_hz)
//   trajectory:                     # exactly one of track / script
//     track: ../../../shared/data/tracks/wuhan_57min_rtk.pos
//     start_offset_s: 0             # piece of the track: [first + offset, first + offset + duration]
//     duration_s: 0                 # 0 = to the end of the track
//     margin_s: 5                   # the piece is fitted with this margin, then trimmed
//     position_cutoff_hz: 0.4
//     attitude_cutoff_hz: 0.3
//     roll_deg_per_g: 4.0           # outward body roll per g of lateral acceleration
//     oscillation_scale: 1.0        # scales the default road oscillations (0 = none)
//     vibration:                    # road/engine vibration as true motion (default none;
//       accel_rms_m_s2: 0.8         #   RoadVibrationOptions in track_trajectory.h): vector rms
//       gyro_rms_deg_s: 0.3         #   of specific force / angular rate at full speed,
//       band_hz: [8, 35]            #   sinusoid frequencies (upper edge < imu_rate_hz / 2),
//       components: 12              #   sinusoids each (linear, angular), >= 3,
//       seed: 1                     #   draws of frequencies and phases (not the case seed),
//       half_amplitude_speed_m_s: 5 #   amplitude factor v^2 / (v^2 + this^2)
//     script:                       # instead of track:
//       start_time_s: 100000
//       start_position: [30.5, 114.3, 20]     # deg, deg, m
//       initial_yaw_deg: 0
//       ramp_s: 1.0
//       segments:
//         - {type: static, duration_s: 60}
//         - {type: accelerate, to_speed_m_s: 10, duration_s: 10}
//         - {type: turn, rate_deg_s: 10, duration_s: 9}
//         - {type: figure_eight, radius_m: 30, laps: 1}
//         - {type: cruise, duration_s: 30}
//         - {type: stop, duration_s: 8}
//   reference_imu:
//     profile: ../imu/pos830_navigation.yaml
//     turn_on_errors: true          # draw constant bias / scale from the profile (sampleErrorModel)
//   tested_imu:
//     profile: ../imu/pos310_tactical.yaml
//     turn_on_errors: true
//     gyro_bias_deg_h: [0.3, -0.2, 0.5]       # extra deterministic terms, added to the draws
//     accel_bias_mg: [0.2, -0.3, 0.1]
//     gyro_scale_ppm: [200, -150, 100]
//     accel_scale_ppm: [-100, 200, 150]
//     gyro_nonorthogonality_urad: [xy, xz, yx, yz, zx, zy]   # off-diagonal N entries
//     accel_nonorthogonality_urad: [xy, xz, yx, yz, zx, zy]
//     g_sensitivity_deg_h_per_g: [9 values, row-major]
//     gyro_bias_per_degC_deg_h: [0.01, 0.02, -0.01]   # temperature coefficient of the bias
//     accel_bias_per_degC_mg: [0.005, 0, 0.01]
//     temperature_ref_degC: 25
//     # Field-mounting geometry relative to the reference IMU (field file only, never the lab):
//     time_offset_s: 0.004                    # tested tags late by this much (tau convention)
//     lever_arm_m: [0.03, -0.02, 0.01]        # tested IMU from the reference IMU, reference body FRD
//     mounting_misalignment_deg: [0.1, -0.2, 0.15]  # rotation of tested body rel. to reference body
//     # Non-linear sensor terms (field and lab files):
//     gyro_scale_asymmetry_pos_ppm: [..3], gyro_scale_asymmetry_neg_ppm: [..3]   (also accel_)
//     gyro_scale_nonlinearity_per_rad_s: [..3]   # k2, y = x + k2 x^2 (SI: 1/(rad/s))
//     accel_scale_nonlinearity_per_m_s2: [..3]   # k2 (SI: 1/(m/s^2))
//     accel_vibration_rectification: {coeff: [..3], regressor: specific_force_hp_sq, window_s: 1}
//                                    # coeff SI per regressor unit (also gyro_)
//     gyro_quantization_rad: [..3]     # increment step (rad); accel_quantization_m_s (m/s)
//   odometer:                       # optional: field/odometer.txt (OdometerSimOptions)
//     rate_hz: 10
//     scale_error_ppm: 3000         # the odometer reads 0.3 % fast
//     noise_std_m_s: 0.05
//     quantization_m_s: 0           # reading step (0: none)
//     lever_arm_m: [0, 0, 0]        # odometer point from the reference IMU, FRD
//     mounting_deg: [0, 0, 0]       # roll, pitch, yaw of the reference IMU in the vehicle frame
//   temperature:                    # optional: tested IMU files get an 8th (temperature) column
//     start_degC: 20                # warm-up T(t) = end + (start - end) exp(-(t - t_file0) / tau)
//     end_degC: 35
//     time_constant_s: 900
//   gnss:
//     rate_hz: 1
//     noise_std_neu_m: [0.02, 0.02, 0.04]
//     lever_arm_m: [0.0, 0.0, -1.2]           # antenna from the reference IMU, FRD
//   lab:
//     latitude_deg: 30.53
//     longitude_deg: 114.35
//     height_m: 25
//     start_time_s: 100000
//     static_duration_s: 3600
//     static_attitude_deg: [0, 0, 0]
//     six_position_duration_s: 60
//     rate_table_deg_s: [10, 30, 60, 100]
//     rate_table_turns: 1
//     tilt_duration_s: 60
//     tilts: {tilt_a: [10, 0, 0], tilt_b: [0, -15, 90]}

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/sim/gnss_simulator.h"
#include "graftnav/imu/imu_error_model.h"
#include "graftnav/imu/imu_profile.h"
#include "graftnav/sim/lab_simulator.h"
#include "graftnav/sim/motion_script.h"
#include "graftnav/sim/odometer_simulator.h"
#include "graftnav/sim/track_trajectory.h"

namespace graftnav {

struct SimTrackSource {
  std::string path;
  double start_offset_s = 0.0;
  double duration_s = 0.0;  // 0 = to the end
  double margin_s = 5.0;
  TrackSmoothingOptions smoothing;
};

// The IMU that a case file records: a profile (its stochastic terms and turn-on draws) plus
// extra deterministic terms.
struct SimImuConfig {
  std::string profile_path;
  ImuProfile profile;
  bool turn_on_errors = true;
  // Multiplies the Gauss-Markov bias instability of the simulated sensor (not the profile written
  // to case.yaml): 0 gives a sensor whose errors are all of the kinds grafting models.
  double bias_instability_scale = 1.0;
  ImuErrorModel extra;  // only deterministic terms are filled by the parser
};

// Sensor temperature of the tested IMU during each file (a warm-up curve from the file's start).
struct SimTemperature {
  double start_degC = 25.0;
  double end_degC = 25.0;
  double time_constant_s = 900.0;
  // Lab files at this constant temperature (a thermally settled bench) instead of warming up
  // from their start like the field file (key temperature.lab_degC; unset: warm-up too).
  std::optional<double> lab_degC;
  double at(double seconds_since_file_start) const;
  // The temperature model of the lab files.
  SimTemperature lab() const;
};

struct SimConfig {
  std::string name = "simulated_case";
  std::string source_path;  // the config file, for messages
  uint64_t seed = 1;
  int gnss_week = 2100;
  double imu_rate_hz = 200.0;
  int quadrature_nodes = 6;
  double truth_rate_hz = 200.0;
  std::optional<SimTrackSource> track;
  std::optional<MotionScript> script;
  SimImuConfig reference_imu;
  SimImuConfig tested_imu;
  GnssSimOptions gnss;
  LabSimOptions lab;
  // Common random numbers (key lab.common_random_numbers): the lab session's noise (white and
  // bias wander) is the same random stream as the field tested IMU's, so lab static sample k
  // carries the noise of field sample k. A variance-reduction design for grafting experiments
  // (graft with grafting.start_offset_s: 0): SG and REAL then differ only by what grafting
  // models or misses, not by two noise realizations. A static record shorter than the field test
  // is extended to its length. Not a physical lab session.
  bool lab_common_random_numbers = false;
  std::optional<SimTemperature> temperature;
  std::optional<OdometerSimOptions> odometer;  // field/odometer.txt when set
  bool ideal = false;  // every IMU error-free and GNSS noise-free (set by --ideal)

  void validate() const;  // throws std::invalid_argument naming the key
};

// Parses a sim config file. Throws std::runtime_error naming file, line and key on a missing
// file, a YAML error, a missing or wrong-typed key or an invalid value; unknown keys go to
// *warnings.
SimConfig loadSimConfig(const std::string& path, std::vector<std::string>* warnings = nullptr);

// The error model of a simulated IMU: the profile's stochastic terms (+ one draw of the turn-on
// bias and scale when turn_on_errors) plus the extra deterministic terms; ideal() when `ideal`.
ImuErrorModel buildSimErrorModel(const SimImuConfig& imu, uint64_t seed, bool ideal);

// The model of the same sensor on the lab bench: `field_model` without the field-mounting
// geometry (time offset, lever arm and misalignment are relative to the reference IMU in the car).
ImuErrorModel labErrorModel(const ImuErrorModel& field_model);

}  // namespace graftnav
