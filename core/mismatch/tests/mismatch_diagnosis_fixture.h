// Shared fixtures of the mismatch finder's end-to-end tests: car-like motion, a synthetic
// reference / real / simulated triple made with the error model, and look-ups in the result.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "graftnav/imu/imu_error_model.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "graftnav/mismatch/term_spec.h"
#include "graftnav/nav/rotation.h"
#include "synthetic_imu.h"

namespace graftnav::diagnosis_test {

// Car-like analytic rates (sinusoids), integrated exactly; a stop at the start.
struct Motion {
  std::array<std::vector<std::array<double, 3>>, 6> waves;  // amp, omega, phase
  Vector6d offset = Vector6d::Zero();
  double rest_s = 20.0;
  // Integral from 0 to t of the rate, with motion ramped in after rest_s (smooth step).
  Vector6d integral(double t) const {
    Vector6d out = offset * t;
    if (t <= rest_s) return out;
    // Integrate numerically the product of the ramp and the waves (Simpson on 1 ms steps is
    // overkill; use the analytic waves times a ramp that is 1 after rest_s + 5 s).
    const double t1 = std::min(t, rest_s + 5.0);
    const int m = 200;
    for (int c = 0; c < 6; ++c) {
      double sum = 0.0;
      for (int k = 0; k < m; ++k) {  // midpoint rule over the ramp interval
        const double u = rest_s + (t1 - rest_s) * (k + 0.5) / m;
        const double ramp = 0.5 - 0.5 * std::cos(M_PI * (u - rest_s) / 5.0);
        for (const auto& w : waves[c]) sum += ramp * w[0] * std::sin(w[1] * u + w[2]);
      }
      out(c) += sum * (t1 - rest_s) / m;
      if (t > rest_s + 5.0)
        for (const auto& w : waves[c])
          out(c) += w[0] / w[1] * (std::cos(w[1] * t1 + w[2]) - std::cos(w[1] * t + w[2]));
    }
    return out;
  }
};

inline Motion carMotion(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Motion m;
  const double amp[6] = {0.04, 0.04, 0.2, 1.2, 1.5, 0.5};
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k < 6; ++k)
      m.waves[c].push_back(
          {amp[c] * (0.3 + U(rng)), 2.0 * M_PI * (0.01 + 0.5 * U(rng)), 2.0 * M_PI * U(rng)});
  m.offset << 0.0, 0.0, 0.0, 0.2, -0.1, -9.79;
  return m;
}

inline ImuSeries sampleMotion(const Motion& m, double rate_hz, double duration_s) {
  return test::sampleIntegral([&m](double t) { return m.integral(t); }, rate_hz, duration_s,
                              5000.0);
}

struct Pair {
  DiagnosisInputs in;
  ImuErrorModel truth;
};

// Reference at 100 Hz with a little white noise; "real" tested at 120 Hz with the given model
// plus MEMS-like white noise and a constant bias; simulation = reference + static bias.
inline Pair makePair(const ImuErrorModel& extra, uint64_t seed) {
  const Motion m = carMotion(seed);
  const double T = 150.0;
  Pair p;
  ImuErrorModel ref_noise;
  ref_noise.gyro.white_noise.density.setConstant(2e-4);
  ref_noise.accel.white_noise.density.setConstant(2e-3);
  p.in.reference = applyErrors(sampleMotion(m, 100.0, T), ref_noise, seed + 1);
  p.truth = extra;
  p.truth.gyro.white_noise.density.setConstant(3e-4);  // 0.017 deg/s/rtHz
  p.truth.accel.white_noise.density.setConstant(3e-3);
  p.truth.gyro.constant_bias.b << 0.01, -0.015, 0.005;
  p.truth.accel.constant_bias.b << 0.1, -0.05, 0.08;
  p.in.real = applyErrors(sampleMotion(m, 120.0, T), p.truth, seed + 2);
  const StaticBiasSimulation sim = simulateFromReferenceAndStaticBias(p.in.reference, p.in.real);
  p.in.simulated = sim.simulated;
  p.in.case_name = "synthetic";
  p.in.simulation_kind = "reference + static bias";
  return p;
}

// White noise only (densities in rad/s/sqrt(Hz) and m/s^2/sqrt(Hz)).
inline ImuErrorModel whiteNoise(double gyro_density, double accel_density) {
  ImuErrorModel m;
  m.gyro.white_noise.density.setConstant(gyro_density);
  m.accel.white_noise.density.setConstant(accel_density);
  return m;
}

// A simulation that applies `simulated_model` to `reference` (as SG#2 grafts the lab's terms)
// against a real tested IMU with `real_model` on the same motion; noise streams seed, seed + 1.
inline DiagnosisInputs graftedInputs(const ImuSeries& reference, const ImuErrorModel& real_model,
                                     const ImuErrorModel& simulated_model, uint64_t seed,
                                     const std::string& simulation_kind) {
  DiagnosisInputs in;
  in.case_name = "synthetic";
  in.simulation_kind = simulation_kind;
  in.reference = reference;
  in.real = applyErrors(reference, real_model, seed);
  in.simulated = applyErrors(reference, simulated_model, seed + 1);
  return in;
}

// Whether some note of r contains both a and b.
inline bool hasNote(const DiagnosisResult& r, const std::string& a, const std::string& b) {
  return std::any_of(r.notes.begin(), r.notes.end(), [&](const std::string& n) {
    return n.find(a) != std::string::npos && n.find(b) != std::string::npos;
  });
}

// The kinds of r's claimed effects.
inline std::set<TermKind> effectKinds(const DiagnosisResult& r) {
  std::set<TermKind> kinds;
  for (const Effect& e : r.effects) kinds.insert(e.kind());
  return kinds;
}

inline const Effect* findEffect(const DiagnosisResult& r, TermKind kind) {
  for (const Effect& e : r.effects)
    if (e.kind() == kind) return &e;
  return nullptr;
}

}  // namespace graftnav::diagnosis_test
