#include "graftnav/mismatch/sample_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace graftnav {
namespace {

Eigen::Vector3d valueOf(const ImuSample& s, SampleQuantity quantity) {
  switch (quantity) {
    case SampleQuantity::angular_rate:
      return s.dtheta_rad / s.dt_s;
    case SampleQuantity::angle_increment:
      return s.dtheta_rad;
    case SampleQuantity::velocity_increment:
      return s.dvel_m_s;
  }
  return s.dvel_m_s;
}

}  // namespace

Eigen::Vector3d blockDifferenceNoiseSd(const ImuSeries& imu, SampleQuantity quantity,
                                       std::size_t block_samples) {
  if (imu.size() < 3)
    throw std::invalid_argument("blockDifferenceNoiseSd: " + std::to_string(imu.size()) +
                                " samples, at least 3 needed");
  return blockDifferenceNoiseSd(viewedRecording(imu), quantity, block_samples);
}

Eigen::Vector3d blockDifferenceNoiseSd(const ImuRecording& imu, SampleQuantity quantity,
                                       std::size_t block_samples) {
  if (imu.samples < 3)
    throw std::invalid_argument("blockDifferenceNoiseSd: " + std::to_string(imu.samples) +
                                " samples, at least 3 needed");
  if (block_samples == 0) throw std::invalid_argument("blockDifferenceNoiseSd: block_samples = 0");
  std::vector<double> per_block[3];
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  bool first = true;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  imu.pass([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      const Eigen::Vector3d value = valueOf(s, quantity);
      if (!first) {
        const Eigen::Vector3d d = value - previous;
        acc += d.cwiseAbs2();
        if (++count == block_samples) {
          for (int a = 0; a < 3; ++a) per_block[a].push_back(0.5 * acc(a) / count);
          acc.setZero();
          count = 0;
        }
      }
      previous = value;
      first = false;
    }
  });
  if (count > 0 && per_block[0].empty())
    for (int a = 0; a < 3; ++a) per_block[a].push_back(0.5 * acc(a) / count);
  Eigen::Vector3d sd;
  for (int a = 0; a < 3; ++a) {
    std::vector<double>& v = per_block[a];
    const std::size_t q = v.size() / 20;
    std::nth_element(v.begin(), v.begin() + q, v.end());
    sd(a) = std::sqrt(v[q]);
  }
  return sd;
}

std::size_t samplesPerSecond(double dt_s) {
  return std::max<std::size_t>(8, static_cast<std::size_t>(std::lround(1.0 / dt_s)));
}

}  // namespace graftnav
