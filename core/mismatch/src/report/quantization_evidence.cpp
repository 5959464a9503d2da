#include "graftnav/mismatch/quantization_evidence.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
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

// Whether one increment is a whole multiple of `unit` (relative tolerance 1e-6 of the unit).
bool onLattice(double value, double unit) {
  const double f = value / unit;
  return !(std::abs(f - std::round(f)) > 1e-6 * std::max(1.0, std::abs(f) * 1e-9));
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
  if (imu.empty()) return Eigen::Vector3d::Zero();
  return printedResolution(viewedRecording(imu), sensor);
}

// Per axis and number of decimals d: whether every increment so far is a multiple of 10^-d.
Eigen::Vector3d printedResolution(const ImuRecording& imu, Sensor sensor) {
  Eigen::Vector3d res = Eigen::Vector3d::Zero();
  if (imu.samples == 0) return res;
  bool all_on[3][kMaxPrintedDecimals + 1];
  double unit[kMaxPrintedDecimals + 1];
  for (int d = 0; d <= kMaxPrintedDecimals; ++d) unit[d] = std::pow(10.0, -d);
  for (auto& axis : all_on) std::fill(std::begin(axis), std::end(axis), true);
  imu.pass([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      const Eigen::Vector3d v = increment(s, sensor);
      for (int a = 0; a < 3; ++a)
        for (int d = 0; d <= kMaxPrintedDecimals; ++d)
          if (all_on[a][d] && !onLattice(v(a), unit[d])) all_on[a][d] = false;
    }
  });
  for (int a = 0; a < 3; ++a)
    for (int d = 0; d <= kMaxPrintedDecimals; ++d)
      if (all_on[a][d]) {
        res(a) = unit[d];
        break;
      }
  return res;
}

QuantizationCheck checkQuantization(const ImuSeries& real, const ImuSeries& simulated,
                                    Sensor sensor, const QuantizationEvidenceOptions& options) {
  if (real.size() < 3 || simulated.empty())
    throw std::invalid_argument("checkQuantization: " + std::to_string(real.size()) +
                                " real samples, at least 3 needed, and a simulation");
  return checkQuantization(viewedRecording(real), viewedRecording(simulated), sensor, options);
}

QuantizationCheck checkQuantization(const ImuRecording& real, const ImuRecording& simulated,
                                    Sensor sensor, const QuantizationEvidenceOptions& options) {
  options.validate();
  QuantizationCheck c;
  c.sensor = sensor;
  c.min_step_over_resolution = options.min_step_over_resolution;
  c.step = detectQuantizationStep(real, sensor);
  c.printed_resolution = printedResolution(real, sensor);
  // One-second blocks at the record's mean sample interval.
  const double span_s = real.last.t_s - real.first.t_s;
  c.white_noise_sd = blockDifferenceNoiseSd(
      real,
      sensor == Sensor::gyro ? SampleQuantity::angle_increment : SampleQuantity::velocity_increment,
      samplesPerSecond(span_s / static_cast<double>(real.samples - 1)));
  const Eigen::Vector3d sim_step = detectQuantizationStep(simulated, sensor);
  c.resolvable_share =
      options.resolvable_sigmas * std::sqrt(2.0 / static_cast<double>(real.samples));
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
