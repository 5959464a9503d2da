#include "graftnav/sim/sampling_grid.h"

#include <cmath>
#include <stdexcept>

namespace graftnav {

std::vector<double> uniformEpochs_s(double t_begin_s, double t_end_s, double rate_hz) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz))
    throw std::invalid_argument("uniformEpochs_s: rate_hz must be positive and finite");
  if (!std::isfinite(t_begin_s) || !std::isfinite(t_end_s))
    throw std::invalid_argument("uniformEpochs_s: the span's ends must be finite");
  const long k0 = static_cast<long>(std::ceil(t_begin_s * rate_hz - 1e-9));
  const long k1 = static_cast<long>(std::floor(t_end_s * rate_hz + 1e-9));
  std::vector<double> epochs_s;
  if (k1 >= k0) epochs_s.reserve(static_cast<std::size_t>(k1 - k0 + 1));
  for (long k = k0; k <= k1; ++k) epochs_s.push_back(static_cast<double>(k) / rate_hz);
  return epochs_s;
}

}  // namespace graftnav
