#pragma once
// The mismatch finder's own tuning constants (DiagnoseOptions::finder): the lab gates, the number
// of passes of its loops, and the sizes below which it does not fit or check. The defaults are
// those every validated result in docs/mismatch.md was produced with; configs/diagnose.yaml can
// set each (same key names).

namespace graftnav {

struct FinderOptions {
  // A term the lab calibration could explain is claimed only beyond this many combined sigmas
  // (fit and lab uncertainty): scale_factor / non_orthogonality / scale_asymmetry /
  // mounting_misalignment gates, and the sensor's own k2 beside the lab's quadratic.
  double lab_gate_sigmas = 3.0;
  // The lab gates refit after holding terms back and run again, at most this many times.
  int max_gate_passes = 4;
  // Claimed terms refitted beside the gated calibration error, at most this many times.
  int max_calibration_refit_passes = 4;
  // The selection runs again with mounting_misalignment linearized at the fitted rotation at
  // most this many times, while its second order 0.5 |phi|^2 exceeds rotation_second_order_min
  // and the rotation moved by more than rotation_rel_change of itself.
  int max_rotation_passes = 2;
  double rotation_second_order_min = 1e-6;
  double rotation_rel_change = 0.01;
  // A joint-fit tau within this of the time_offset pivot is its own pivot (s); farther, the
  // selection runs again around it.
  double pivot_tolerance_s = 1e-5;
  // A cross-correlation pivot below this fraction of a bin is taken as 0 (derivative regressor).
  double min_pivot_bins = 0.025;
  // The grid keeps |pivot| + this from the records' ends when that exceeds margin_s (s).
  double pivot_margin_s = 0.5;
  // Fewest bins the records must overlap by.
  int min_grid_bins = 100;
  // The slow-noise block is shortened so that the record holds at least this many blocks.
  int min_slow_blocks = 8;
  // Fewest bins per half for the held-out check.
  int min_holdout_bins = 200;
  // A claimed scale factor below this many times the reference IMU's stated scale uncertainty
  // is noted as possibly the reference's own gain error.
  double reference_scale_share_limit = 5.0;
  void validate() const;  // throws std::invalid_argument naming the field and value
};

}  // namespace graftnav
