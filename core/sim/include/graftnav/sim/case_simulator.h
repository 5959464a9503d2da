#pragma once
// Writes a whole simulated case (layout of spec/dataset.md) from a SimConfig:
//   case.yaml, field/ref_imu.txt, field/tested_imu.txt, field/gnss.pos, field/truth.nav,
//   field/odometer.txt (when the config has an odometer section),
//   lab/static.txt, lab/six_position/*, lab/rate/*, lab/tilt/*, and simulation.yaml (the seed
//   and the drawn error terms of both IMUs, for checking calibration and grafting results).
// Randomness: every stream derives from the one seed (deriveStreamSeed): reference IMU 1, tested
// IMU field 2, tested turn-on draw 3, reference turn-on draw 4, GNSS 5, odometer 6, lab session
// i 100 + i.
// The tested IMU keeps the same deterministic terms (turn-on draw included) in the field and in
// the lab, so that lab-derived errors apply to the field record; noise realizations differ.

#include <functional>
#include <string>

#include "graftnav/sim/sim_config.h"

namespace graftnav {

struct CaseSimSummary {
  double t_begin_s = 0.0, t_end_s = 0.0;
  std::size_t imu_samples = 0, gnss_fixes = 0, truth_epochs = 0, lab_files = 0;
  double path_length_m = 0.0;
  TrackFitReport track_fit;  // when the source is a track
};

// Progress messages ("field IMU 40%") go to `progress` when given; nothing is printed.
CaseSimSummary simulateCase(const SimConfig& config, const std::string& case_dir,
                            const std::function<void(const std::string&)>& progress = {});

}  // namespace graftnav
