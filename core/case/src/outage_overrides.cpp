#include "graftnav/case/outage_overrides.h"

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

namespace graftnav {
namespace {

void requirePositive(const std::optional<double>& v, const char* flag) {
  if (v && !(std::isfinite(*v) && *v > 0.0))
    throw std::runtime_error(fmt::format("{} {}: must be a positive number of seconds", flag, *v));
}

}  // namespace

void OutageOverrides::validate() const {
  requirePositive(length_s, "--outage-length");
  requirePositive(period_s, "--outage-period");
  if (start_s && !(std::isfinite(*start_s) && *start_s >= 0.0))
    throw std::runtime_error(
        fmt::format("--outage-start {}: must be >= 0 s (seconds after the data start)", *start_s));
  if (length_s && period_s && *period_s < *length_s)
    throw std::runtime_error(
        fmt::format("--outage-period {} is shorter than --outage-length {}: outages would overlap",
                    *period_s, *length_s));
}

OutageScheduleConfig OutageOverrides::appliedTo(OutageScheduleConfig base) const {
  if (length_s) base.length_s = *length_s;
  if (period_s) base.period_s = *period_s;
  if (start_s) base.start_s = *start_s;
  return base;
}

}  // namespace graftnav
