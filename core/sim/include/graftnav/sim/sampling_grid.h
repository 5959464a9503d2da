#pragma once
// The epochs of a sensor sampled on whole multiples of its period in GNSS time: t_k = k / rate_hz
// for every integer k with t_begin_s <= t_k <= t_end_s (1e-9 of a period of slack at each end,
// so an end that is itself a sample is kept). GNSS fixes and odometer readings are simulated on
// this grid, so their stamps fall on the same whole seconds whatever the span.

#include <vector>

namespace graftnav {

// Throws std::invalid_argument when rate_hz is not positive and finite or an end is not finite.
std::vector<double> uniformEpochs_s(double t_begin_s, double t_end_s, double rate_hz);

}  // namespace graftnav
