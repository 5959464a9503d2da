#pragma once
// The run config's vehicle-aiding sections (docs/aiding.md), parsed with the rest of the run
// config (run_config.h) and handed to every estimator through EstimationProblem::aiding:
//
//   odometer:
//     enabled: false
//     std_m_s: 0.05                      # forward; or [forward, lateral, vertical]
//     scale_std_ppm: 10000               # initial 1-sigma of the scale error (0: not estimated)
//     scale_random_walk_ppm_sqrt_s: 0
//     lever_arm_m: [0, 0, 0]             # odometer point from the IMU, body FRD (NHC's point too)
//     mounting_deg: [0, 0, 0]            # roll, pitch, yaw of the IMU body in the vehicle frame
//     rate_hz: 10                        # EKF/RTS update rate, graph node rate
//     max_gap_s: 0.5                     # no speed across a wider gap between samples
//     forward_only: true                 # a negative speed in field/odometer.txt is an error
//   nhc:
//     enabled: false
//     std_m_s: 0.1                       # lateral and vertical; or [lateral, vertical]
//     rate_hz: 10
//
// Units convert here, once: ppm -> fraction, degrees -> radians.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "graftnav/estimation/vehicle_aiding.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/io/yaml_fields.h"

namespace graftnav {

struct AidingConfig {
  VehicleAidingOptions options;       // what the estimators use
  OdometerReadOptions odometer_read;  // how field/odometer.txt is read (forward_only)
};

const std::vector<std::string>& odometerSectionKeys();
const std::vector<std::string>& nhcSectionKeys();

// Read over *c (a key not given keeps its value); errors name the source, line and dotted key.
void parseOdometerSection(const yaml_fields::Context& ctx, const YAML::Node& section,
                          AidingConfig* c);
void parseNhcSection(const yaml_fields::Context& ctx, const YAML::Node& section, AidingConfig* c);
// After both sections: the options' own checks (VehicleAidingOptions::validate), naming the key.
void validateAidingConfig(const yaml_fields::Context& ctx, const AidingConfig& c);

}  // namespace graftnav
