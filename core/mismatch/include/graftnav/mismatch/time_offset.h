#pragma once
// Time offset between a tested IMU record and a simulation of it (or the reference signals),
// estimated before anything else because every other term is fitted on aligned signals.
//
// Convention: tau_s > 0 when the tested IMU's time tags are late, i.e. the tested
// sample tagged t was measured at t - tau_s: tested(t) = x(t - tau_s). The cross-covariance
// c(L) = sum_t x(t) tested(t + L) of the mean-removed angular rates (bins of bin_s, summed over
// the three axes so that the axis with most motion dominates) peaks at L = tau_s; the peak is
// located to a fraction of a bin by a parabola through the three best lags. Two stages: a coarse
// search over +/- coarse_max_offset_s on coarse_bin_s bins (separately started loggers can be
// seconds apart), then the fine search over +/- max_offset_s around the coarse peak.
//
// Why this is not the GNSS latency estimator (eval/gnss_latency.h), and the joint fit
// (joint_fit.h) is not a third estimator: the three answer different questions on different
// data. Here two dense records of the same quantity (angular rates at 100-200 Hz) are compared,
// so their cross-correlation peak finds an offset of seconds without a model. GNSS latency
// compares sparse position fixes (1 Hz) with a trajectory, where no correlation exists and the
// shift is found by the horizontal residual RMS it leaves (plus a slope estimate), per fix and
// with outliers dropped. The joint fit does not estimate an offset on its own: it refines this
// one, started at its pivot, as a non-linear parameter beside every other selected term, which
// the cross-correlation cannot (a lever arm or misalignment would bias it). The shared part of
// the first two, a parabola through the best three grid points, is three lines.

#include <Eigen/Core>

#include "graftnav/mismatch/common_grid.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct TimeOffsetOptions {
  double bin_s = 0.01;                // averaging bin of the correlation (s)
  double max_offset_s = 0.5;          // fine search range +/- (s) around the coarse peak
  double coarse_bin_s = 0.05;         // bins of the coarse search (s)
  double coarse_max_offset_s = 10.0;  // coarse search range +/- (s), capped at a quarter of the
                                      // overlap; <= max_offset_s: no coarse stage
  double min_correlation = 0.3;       // below this peak correlation the estimate is not trusted
  void validate() const;              // throws std::invalid_argument naming the field
};

struct TimeOffsetEstimate {
  double tau_s = 0.0;             // positive: tested tags late
  double peak_correlation = 0.0;  // normalized correlation at the peak (1 = identical shapes)
  bool reliable = false;          // peak_correlation >= min_correlation and not at the range edge
};

// Cross-correlation estimate of the offset of `tested` relative to `reference`.
TimeOffsetEstimate estimateTimeOffset(const ImuSeries& reference, const ImuSeries& tested,
                                      const TimeOffsetOptions& options = {});
// The same from passes of the recordings (each binning reads both once).
TimeOffsetEstimate estimateTimeOffset(const ImuRecording& reference, const ImuRecording& tested,
                                      const TimeOffsetOptions& options = {});

// Regressor of a time offset on the grid: the residual tested - reference of a shift tau is
// x(t - tau) - x(t) = tau u(t). With pivot_s != 0 the chord u = (x(t - pivot) - x(t)) / pivot is
// returned (exact at tau = pivot, so a large offset stays linear); with pivot_s == 0 the
// derivative u = -dx/dt (central differences of the bin means). Columns [omega (3), f (3)].
// `response`, when given, maps each reference sample first (the tested IMU's response to it).
Eigen::MatrixXd timeOffsetRegressor(const ImuSeries& reference, const GridSpec& grid,
                                    double pivot_s, const ImuSampleMap& response = {});

}  // namespace graftnav
