#pragma once
// Whether a value lattice of the tested IMU's increments is the sensor's quantization or only the
// text format it was written in, and whether its noise matters beside the white noise.
//
// A file written with d fixed decimals puts every increment on a lattice of 10^-d (the printed
// resolution), whatever the sensor did: loggers write fixed decimals too. The printed resolution
// is read from the values: the coarsest power of ten of which every value is a whole multiple
// (0 when none down to 1e-12, e.g. values written with significant digits or in binary). A
// lattice at a power of ten is indistinguishable from printing and is never claimed.
//
// Quantization is claimed on an axis only when
//   (a) its step q exceeds min_step_over_resolution times the printed resolution, and
//   (b) its noise, q^2 / 12 per sample, is resolvable against the white noise sigma_w^2 per
//       sample of the same record: q^2 / 12 >= resolvable_sigmas * sqrt(2 / N) * sigma_w^2, the
//       standard error of a variance estimated from the record's N samples. Below it the
//       quantization does not change the noise a navigation filter sees by more than the record
//       can measure.
// The step that (b) needs, sqrt(12 resolvable_sigmas sqrt(2 / N)) sigma_w, is the detection limit.

#include <Eigen/Core>
#include <string>

#include "graftnav/io/imu_recording.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct QuantizationEvidenceOptions {
  double min_step_over_resolution = 1.5;  // (a): a lattice step must be at least 2 printed units
  double resolvable_sigmas = 3.0;         // (b): standard errors of the white-noise variance
  void validate() const;
};

// Per axis of one sensor of the tested record.
struct QuantizationCheck {
  Sensor sensor = Sensor::gyro;
  Eigen::Vector3d step = Eigen::Vector3d::Zero();                // lattice step (0: none)
  Eigen::Vector3d printed_resolution = Eigen::Vector3d::Zero();  // 10^-d (0: not fixed decimals)
  Eigen::Vector3d white_noise_sd = Eigen::Vector3d::Zero();      // per sample (rad, m/s)
  Eigen::Vector3d noise_share = Eigen::Vector3d::Zero();         // (q^2 / 12) / sigma_w^2
  double resolvable_share = 0.0;                                 // resolvable_sigmas sqrt(2 / N)
  double min_step_over_resolution = 1.5;                         // the option (a) was checked with
  Eigen::Vector3d detectable_step = Eigen::Vector3d::Zero();     // the step (b) needs
  bool simulation_on_same_lattice = false;  // the simulation's increments share the step
  bool claimed[3] = {false, false, false};
  bool anyClaimed() const { return claimed[0] || claimed[1] || claimed[2]; }
  // Plain-language verdict per axis for the report.
  std::string summary() const;
};

// The coarsest 10^-d (d = 0..12) of which every increment of the axis is a whole multiple
// (relative tolerance 1e-6 of the printed unit), 0 when there is none.
Eigen::Vector3d printedResolution(const ImuSeries& imu, Sensor sensor);
Eigen::Vector3d printedResolution(const ImuRecording& imu, Sensor sensor);  // in one pass

// The verdict for one sensor: `real` is the tested record, `simulated` the simulation (a lattice
// both share is not missing from the simulation). Throws std::invalid_argument with fewer than
// 3 samples.
QuantizationCheck checkQuantization(const ImuSeries& real, const ImuSeries& simulated,
                                    Sensor sensor, const QuantizationEvidenceOptions& options = {});
// The same from passes of the two recordings (none is held).
QuantizationCheck checkQuantization(const ImuRecording& real, const ImuRecording& simulated,
                                    Sensor sensor, const QuantizationEvidenceOptions& options = {});

}  // namespace graftnav
