#include "graftnav/mismatch/quantization_evidence.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/core.h>

#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/sample_noise.h"

namespace graftnav {
namespace {

constexpr int kMaxPrintedDecimals = 12;

Eigen::Vector3d increment(const ImuSample& s, Sensor sensor) {
  return sensor == Sensor::gyro ? s.dtheta_rad : s.dvel_m_s;
}

bool allOnLattice(const ImuSeries& imu, Sensor sensor, int axis, double unit) {
  for (const ImuSample& s : imu) {
    const double f = increment(s, sensor)(axis) / unit;
    if (std::abs(f - std::round(f)) > 1e-6 * std::max(1.0, std::abs(f) * 1e-9)) return false;
  }
  return true;
}

}  // namespace

void QuantizationEvidenceOptions::validate() const {
  if (!(min_step_over_resolution >= 1.0) || !std::isfinite(min_step_over_resolution))
    throw std::invalid_argument("QuantizationEvidenceOptions: min_step_over_resolution = " +
                                std::to_string(min_step_over_resolution) + " must be >= 1");
  if (!(resolvable_sigmas > 0.0) || !std::isfinite(resolvable_sigmas))
    throw std::invalid_argument("QuantizationEvidenceOptions: resolvable_sigmas = " +
                                std::to_string(resolvable_sigmas) + " must be > 0");
}

Eigen::Vector3d printedResolution(const ImuSeries& imu, Sensor sensor) {
  Eigen::Vector3d res = Eigen::Vector3d::Zero();
  if (imu.empty()) return res;
  for (int a = 0; a < 3; ++a) {
    for (int d = 0; d <= kMaxPrintedDecimals; ++d) {
      const double unit = std::pow(10.0, -d);
      if (allOnLattice(imu, sensor, a, unit)) {
        res(a) = unit;
        break;
      }
    }
  }
  return res;
}

QuantizationCheck checkQuantization(const ImuSeries& real, const ImuSeries& simulated,
                                    Sensor sensor, const QuantizationEvidenceOptions& options) {
  options.validate();
  QuantizationCheck c;
  c.sensor = sensor;
  c.min_step_over_resolution = options.min_step_over_resolution;
  c.step = detectQuantizationStep(real, sensor);
  c.printed_resolution = printedResolution(real, sensor);
  // One-second blocks at the record's mean sample interval.
  const double span_s = real.back().t_s - real.front().t_s;
  c.white_noise_sd = blockDifferenceNoiseSd(
      real,
      sensor == Sensor::gyro ? SampleQuantity::angle_increment : SampleQuantity::velocity_increment,
      samplesPerSecond(span_s / static_cast<double>(real.size() - 1)));
  const Eigen::Vector3d sim_step = detectQuantizationStep(simulated, sensor);
  c.resolvable_share =
      options.resolvable_sigmas * std::sqrt(2.0 / static_cast<double>(real.size()));
  for (int a = 0; a < 3; ++a) {
    const double q = c.step(a), var_w = c.white_noise_sd(a) * c.white_noise_sd(a);
    c.noise_share(a) = var_w > 0.0 ? q * q / 12.0 / var_w : 0.0;
    c.detectable_step(a) = std::sqrt(12.0 * c.resolvable_share) * c.white_noise_sd(a);
    const bool same_as_sim = q > 0.0 && std::abs(sim_step(a) - q) <= 1e-3 * q;
    c.simulation_on_same_lattice |= same_as_sim;
    const bool beyond_printing =
        q > 0.0 && q > options.min_step_over_resolution * c.printed_resolution(a);
    c.claimed[a] = beyond_printing && !same_as_sim && c.noise_share(a) >= c.resolvable_share;
  }
  return c;
}

std::string QuantizationCheck::summary() const {
  std::string s;
  const char* axes = "xyz";
  for (int a = 0; a < 3; ++a) {
    std::string v;
    if (!(step(a) > 0.0))
      v = "no lattice";
    else if (printed_resolution(a) > 0.0 &&
             !(step(a) > min_step_over_resolution * printed_resolution(a)))
      v = fmt::format("step {:.3g} = the printed resolution {:.3g} (text format, not the sensor)",
                      step(a), printed_resolution(a));
    else
      v = fmt::format(
          "step {:.3g} (printed resolution {:.3g}), noise q^2/12 = {:.3g} of the white "
          "noise variance (resolvable from {:.3g}; step needed {:.3g}){}",
          step(a), printed_resolution(a), noise_share(a), resolvable_share, detectable_step(a),
          claimed[a] ? ": claimed" : ": not resolvable");
    s += fmt::format("{}{} {}: {}", s.empty() ? "" : "; ", sensorName(sensor), axes[a], v);
  }
  return s;
}

}  // namespace graftnav
