// Shared fixtures of the mismatch finder's signal-level tests: car-like analytic motion sampled
// exactly, regressor inputs built from it, AR(1) noise, and term look-up.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "graftnav/eval/evaluation.h"
#include "graftnav/imu/gauss_markov.h"
#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/term_selection.h"
#include "graftnav/mismatch/term_spec.h"
#include "graftnav/mismatch/time_offset.h"
#include "graftnav/nav/rotation.h"
#include "synthetic_imu.h"

namespace graftnav::mismatch_test {

// Car-like analytic motion: each channel a sum of sinusoids, integrated exactly over samples.
struct Wave {
  double amp, omega, phase;
};
struct Motion {
  std::array<std::vector<Wave>, 6> waves;
  Vector6d offset = Vector6d::Zero();
  Vector6d integral(double t) const {  // integral from 0 to t
    Vector6d out = offset * t;
    for (int c = 0; c < 6; ++c)
      for (const Wave& w : waves[c])
        out(c) += w.amp / w.omega * (std::cos(w.phase) - std::cos(w.omega * t + w.phase));
    return out;
  }
};

inline Motion carMotion(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Motion m;
  const double amp[6] = {0.05, 0.05, 0.25, 1.5, 2.0, 0.6};
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k < 6; ++k)
      m.waves[c].push_back(
          {amp[c] * (0.3 + U(rng)), 2.0 * M_PI * (0.005 + 0.4 * U(rng)), 2.0 * M_PI * U(rng)});
  m.offset << 0.0, 0.0, 0.0, 0.1, -0.2, -9.79;
  return m;
}

inline ImuSeries sampleMotion(const Motion& m, double rate_hz, double duration_s,
                              double tau_s = 0.0, double t0_s = 1000.0) {
  ImuSeries out;
  const int n = static_cast<int>(duration_s * rate_hz);
  for (int k = 1; k <= n; ++k) {
    const double t1 = k / rate_hz, t0 = (k - 1) / rate_hz;
    // Tags late by tau: the sample tagged t covers true time (t0 - tau, t1 - tau].
    const Vector6d inc = m.integral(t1 - tau_s) - m.integral(t0 - tau_s);
    ImuSample s;
    s.t_s = t0_s + t1;
    s.dt_s = 1.0 / rate_hz;
    s.dtheta_rad = inc.head<3>();
    s.dvel_m_s = inc.tail<3>();
    out.push_back(s);
  }
  return out;
}

// Regressor inputs from the analytic motion, with temperature, vibration level and attitude.
inline RegressorInputs syntheticInputs(const Motion& m, double duration_s, double pivot_s) {
  const ImuSeries ref = sampleMotion(m, 100.0, duration_s);
  const GridSpec g = commonGrid(ref, ref, 0.05);
  RegressorInputs in;
  in.reference = binImu(ref, g);
  in.time_offset_column = timeOffsetRegressor(ref, g, pivot_s);
  const int n = g.count;
  in.tested_temperature_degC.resize(n);
  for (int i = 0; i < n; ++i)
    in.tested_temperature_degC(i) = 20.0 + 12.0 * (1.0 - std::exp(-i * g.bin_s / 150.0));
  in.vibration_f_hp_sq = vibrationLevelPerBin(ref, g, "specific_force_hp_sq");
  in.vibration_w_hp_sq = vibrationLevelPerBin(ref, g, "angular_rate_hp_sq");
  in.C_bn.resize(n);
  double yaw = 0.3, pitch = 0.0, roll = 0.0;
  for (int i = 0; i < n; ++i) {
    yaw += in.reference.omega_rad_s(i, 2) * g.bin_s;
    pitch += in.reference.omega_rad_s(i, 1) * g.bin_s;
    roll += in.reference.omega_rad_s(i, 0) * g.bin_s;
    const Eigen::Matrix3d C_nb = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    in.C_bn[i] = C_nb.transpose();
  }
  const double lat = 0.5, we = 7.292115e-5;
  in.omega_ie_n << we * std::cos(lat), 0.0, -we * std::sin(lat);
  return in;
}

// AR(1) noise per channel: gyro and accel scales typical of a 0.05 s bin of a MEMS IMU.
inline Eigen::MatrixXd ar1Noise(int n, double rho, uint64_t seed) {
  StandardNormalSampler rng(seed);
  const double scale[6] = {2e-3, 2e-3, 2e-3, 2e-2, 2e-2, 2e-2};
  Eigen::MatrixXd e(n, 6);
  for (int c = 0; c < 6; ++c) {
    double x = rng.next();
    for (int i = 0; i < n; ++i) {
      x = rho * x + std::sqrt(1.0 - rho * rho) * rng.next();
      e(i, c) = scale[c] * x;
    }
  }
  return e;
}

inline int findTerm(const std::vector<CandidateTerm>& terms, const TermKey& key) {
  for (std::size_t t = 0; t < terms.size(); ++t)
    if (terms[t].key() == key) return static_cast<int>(t);
  return -1;
}

inline std::vector<double> G9() {
  return {2e-4, -1e-4, 3e-4, 1e-4, 2e-4, -2e-4, -3e-4, 1e-4, 2e-4};
}

// The nuisance constant per channel over n bins, as the library's first term.
inline CandidateTerm constantNuisance(int n) {
  CandidateTerm t(termSpec(TermKind::constant_bias), SensorScope::both);
  for (int c = 0; c < 6; ++c) {
    RegressorColumn col;
    col.channel[c] = Eigen::VectorXd::Ones(n);
    t.columns.push_back(col);
  }
  return t;
}

}  // namespace graftnav::mismatch_test
