#pragma once
// Per-sample white noise of an IMU record from its first differences: the one estimate behind the
// lever-arm regressor's window choice (candidate_terms.h) and the quantization check's noise
// share (quantization_evidence.h).
#include <Eigen/Core>
#include <cstddef>

#include "graftnav/io/imu_recording.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// The per-sample series whose white noise is estimated.
enum class SampleQuantity {
  angular_rate,        // dtheta / dt (rad/s)
  angle_increment,     // dtheta (rad)
  velocity_increment,  // dvel (m/s)
};

// Per-axis white noise (standard deviation per sample) of `quantity`: half the mean squared first
// difference over blocks of `block_samples` differences, the 5th percentile over the blocks (the
// quietest, e.g. standstills; an upper bound when the record never rests). A record shorter than
// one block is one block. Throws std::invalid_argument with fewer than 3 samples or
// block_samples 0.
Eigen::Vector3d blockDifferenceNoiseSd(const ImuSeries& imu, SampleQuantity quantity,
                                       std::size_t block_samples);
// The same over one pass of a recording.
Eigen::Vector3d blockDifferenceNoiseSd(const ImuRecording& imu, SampleQuantity quantity,
                                       std::size_t block_samples);

// The block length of the estimate: the samples in one second at sample interval dt_s, at least 8.
std::size_t samplesPerSecond(double dt_s);

}  // namespace graftnav
