#include "graftnav/mismatch/finder_options.h"

#include <fmt/core.h>

#include <stdexcept>

namespace graftnav {

namespace {

void require(bool ok, const char* key, double value, const char* what) {
  if (!ok)
    throw std::invalid_argument(
        fmt::format("FinderOptions: {} = {:g} must be {}", key, value, what));
}

}  // namespace

void FinderOptions::validate() const {
  require(lab_gate_sigmas > 0.0, "lab_gate_sigmas", lab_gate_sigmas, "> 0");
  require(max_gate_passes >= 1, "max_gate_passes", max_gate_passes, ">= 1");
  require(max_calibration_refit_passes >= 1, "max_calibration_refit_passes",
          max_calibration_refit_passes, ">= 1");
  require(max_rotation_passes >= 0, "max_rotation_passes", max_rotation_passes, ">= 0");
  require(rotation_second_order_min >= 0.0, "rotation_second_order_min", rotation_second_order_min,
          ">= 0");
  require(rotation_rel_change >= 0.0 && rotation_rel_change < 1.0, "rotation_rel_change",
          rotation_rel_change, "in [0, 1)");
  require(pivot_tolerance_s > 0.0, "pivot_tolerance_s", pivot_tolerance_s, "> 0");
  require(min_pivot_bins >= 0.0 && min_pivot_bins < 1.0, "min_pivot_bins", min_pivot_bins,
          "in [0, 1)");
  require(pivot_margin_s >= 0.0, "pivot_margin_s", pivot_margin_s, ">= 0");
  require(min_grid_bins >= 10, "min_grid_bins", min_grid_bins, ">= 10");
  require(min_slow_blocks >= 2, "min_slow_blocks", min_slow_blocks, ">= 2");
  require(min_holdout_bins >= 10, "min_holdout_bins", min_holdout_bins, ">= 10");
  require(reference_scale_share_limit > 0.0, "reference_scale_share_limit",
          reference_scale_share_limit, "> 0");
}

}  // namespace graftnav
