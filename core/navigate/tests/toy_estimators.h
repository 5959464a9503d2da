#pragma once
// Toy estimators for the navigate and compare pipelines' tests: fast, deterministic, with both
// forms or only the in-memory one.
#include <string>

#include "graftnav/estimation/estimator_registry.h"

namespace graftnav::test {

// One epoch per IMU sample: the initial state drifting north at `drift_rad_s` of latitude, a
// constant sigma, and sensor estimates that vary with time, so every file has non-trivial
// columns.
inline void toyEpoch(const EstimationProblem& p, const ImuSample& s, double drift_rad_s,
                     double sigma_m, SolutionSink& sink) {
  NavState st = p.initial;
  const double dt_s = s.t_s - p.initial.t_s;
  st.t_s = s.t_s;
  st.pos.lat_rad += drift_rad_s * dt_s;
  PvaSigma sigma = PvaSigma::Constant(sigma_m);
  ImuErrorEstimate e;
  e.gyro_bias_rad_s.x() = 1e-6 * dt_s;
  e.accel_scale.z() = 1e-7 * dt_s;
  sink.add(st, &sigma, e);
}

// A toy estimator `name`; streamed: with its streamed form too.
inline EstimatorEntry toyEntry(const std::string& name, double drift_rad_s, double sigma_m,
                               bool streamed, int gnss_used = 100) {
  EstimatorEntry e{name,
                   "the initial state, drifting",
                   [=](const EstimationProblem& p, const EstimatorOptions&, const ProgressFn&) {
                     NavSolution sol;
                     NavSolutionSink sink(&sol);
                     for (const ImuSample& s : p.imu) toyEpoch(p, s, drift_rad_s, sigma_m, sink);
                     sol.estimator = name;
                     sol.gnss_used = gnss_used;
                     return sol;
                   },
                   {}};
  if (streamed)
    e.stream = [=](const EstimationProblem& p, const ImuPassFn& imu, const EstimatorOptions&,
                   SolutionSink& sink) {
      imu([&](const ImuSeries& block) {
        for (const ImuSample& s : block) toyEpoch(p, s, drift_rad_s, sigma_m, sink);
      });
      NavSolution book;
      book.estimator = name;
      book.gnss_used = gnss_used;
      return book;
    };
  return e;
}

// "hold" (streamed or not) and "coast" (in memory, no GNSS).
inline EstimatorRegistry toyRegistry(bool streamed, int gnss_used = 100) {
  EstimatorRegistry r;
  r.add(toyEntry("hold", 1.6e-10, 0.5, streamed, gnss_used));
  EstimatorEntry coast = toyEntry("coast", 1.6e-10, 0.5, false);
  coast.uses_gnss = false;
  r.add(coast);
  return r;
}

}  // namespace graftnav::test
