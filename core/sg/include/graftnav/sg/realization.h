#pragma once
// Grafted realizations: what changes between two power-ons of the same tested IMU, drawn K times
// so that ERR_SG becomes a predictive distribution instead of a single number.
//
// Realization k varies
//   - the lab-noise segment: where the field test starts in the tiled lab record
//     (GraftOptions::start_offset_s). When the static record is at least K field spans long, the
//     K segments are disjoint (stratum k of the record holds segment k). Otherwise the offsets are
//     stratified over the mirror period 2T of the tiled record, so that no two realizations take
//     the same lab sample at the same field time; they still share the record's slow content
//     (its mean bias and any wander slower than T), which the next two draws replace;
//   - the turn-on bias: a constant per axis, normal with variance sigma_rep^2 (1 + 1/n), where
//     sigma_rep is the bias repeatability (turn-on to turn-on) and n the number of lab sessions
//     whose mean bias the grafted record stands for: the field bias differs from the lab's by one
//     turn-on draw plus the error of the lab's estimate of the mean;
//   - the bias-wander path: when the field test is longer than the record, a first-order
//     Gauss-Markov path (the profile's bias instability and correlation time) sampled every T and
//     linear in between, starting at zero; the record itself carries the wander faster than T.
// Draw k depends only on (seed, k), so a run is reproducible whatever the thread schedule. K = 1 is
// the seed's single graft: only the segment is drawn, no turn-on bias and no wander.

#include <cstdint>
#include <vector>

#include "graftnav/imu/imu_profile.h"
#include "graftnav/sg/grafting.h"

namespace graftnav {

struct RealizationOptions {
  int count = 20;  // K. 19 is the smallest K whose extreme order statistics bound a 90 % interval.
  std::uint64_t seed = 1;
  int lab_sessions = 1;          // n: sessions whose mean bias the lab record stands for
  bool vary_segment = true;
  bool vary_turn_on_bias = true;
  bool vary_bias_wander = true;
  // Throws std::invalid_argument naming the field when out of range.
  void validate() const;
};

struct RealizationDraw {
  int index = 0;
  double start_offset_s = 0.0;  // where the field test starts in the tiled lab record
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
// equal modulo the mirror period 2T, within half a lab sample); 0 when every pair differs.
double sharedSampleFraction(const std::vector<RealizationDraw>& draws, const BasicErrorSignal& basic);

}  // namespace graftnav
