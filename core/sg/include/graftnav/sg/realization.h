#pragma once
// Grafted realizations: what changes between two power-ons of the same tested IMU, drawn K times
// so that ERR_SG becomes a predictive distribution instead of a single number.
//
// Realization k varies
//   - the lab noise: when the static record is at least K field spans long, its own segment
//     (GraftOptions::start_offset_s; stratum k of the record holds segment k, so the K segments
//     are disjoint). Otherwise a phase-randomized surrogate of the record
//     (GraftOptions::surrogate_seed, sg/noise_surrogate.h): segments of a short record would
//     reuse the same few minutes of noise in another order, and on the 15-minute MEMS
//     calibration cases the predictive interval then covered ERR_REAL in only 70-80 % of seeds
//     on vertical, roll and pitch.
//     The surrogate keeps the record's mean (the lab bias) and its spectrum at periods up to
//     slow_period_s; slower content (the in-outage bias wander) is drawn from the profile's
//     noise model (white noise and Gauss-Markov wander, SlowNoiseModel), because the record holds
//     only a few cycles of it and every realization would share that one draw. The offsets are
//     still stratified over the mirror period 2T;
//   - the turn-on bias: a constant per axis, normal with variance sigma_rep^2 (1 + 1/n), where
//     sigma_rep is the bias repeatability (turn-on to turn-on) and n the number of lab sessions
//     whose mean bias the grafted record stands for: the field bias differs from the lab's by one
//     turn-on draw plus the error of the lab's estimate of the mean;
//   - the bias-wander path: when the field test is longer than what the record holds (T, or 2T
//     for a surrogate with modelled slow content), a first-order Gauss-Markov path (the
//     profile's bias instability and correlation time) sampled at that step and linear in
//     between, starting at zero; the record or its surrogate carries the faster wander itself.
// Draw k depends only on (seed, k), so a run is reproducible whatever the thread schedule. K = 1 is
// the seed's single graft: only the segment is drawn, no turn-on bias and no wander.

#include <cstdint>
#include <optional>
#include <vector>

#include "graftnav/imu/imu_profile.h"
#include "graftnav/sg/grafting.h"
#include "graftnav/sg/noise_surrogate.h"

namespace graftnav {

struct RealizationOptions {
  int count = 20;  // K. 19 is the smallest K whose extreme order statistics bound a 90 % interval.
  std::uint64_t seed = 1;
  int lab_sessions = 1;  // n: sessions whose mean bias the lab record stands for
  bool vary_segment = true;
  bool vary_turn_on_bias = true;
  bool vary_bias_wander = true;
  // A record shorter than the field test: draw a surrogate of the lab noise per realization
  // (false: stratified segments of the record itself, intervals too narrow on short records).
  // A record of one to K field spans takes stratified offsets of the record itself.
  bool surrogate_short_record = true;
  // Surrogate content of period longer than this (s) is drawn from the profile's noise model;
  // 0: keep the record's own spectrum at every period. 20 s: at least 30 cycles of what is kept
  // in a 10-minute record (its band power then within about 20 %), and shorter than the outages.
  double slow_period_s = 20.0;
  // Throws std::invalid_argument naming the field when out of range.
  void validate() const;
};

struct RealizationDraw {
  int index = 0;
  double start_offset_s = 0.0;  // where the field test starts in the tiled lab record
  std::optional<std::uint64_t> surrogate_seed;  // set: graft a surrogate of the record (above)
  std::optional<SlowNoiseModel> slow_noise;     // its slow content's model, when slow_period_s > 0
  PowerOnErrors power_on;
};

// The K draws for a field test of `field_span_s` seconds grafted from `basic`, with the
// repeatability, bias instability and correlation times of the tested IMU's `profile`.
std::vector<RealizationDraw> drawRealizations(const RealizationOptions& options,
                                              const BasicErrorSignal& basic,
                                              const ImuProfile& profile, double field_span_s);

// GraftOptions for one draw (start offset resolved, power-on errors set).
GraftOptions graftOptionsFor(const RealizationDraw& draw);

// Fraction of realization pairs that take the same lab sample at every field time (start offsets
// equal modulo the mirror period 2T, within half a lab sample, both grafting the record itself);
// 0 when every pair differs.
double sharedSampleFraction(const std::vector<RealizationDraw>& draws,
                            const BasicErrorSignal& basic);

}  // namespace graftnav
