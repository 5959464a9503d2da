#pragma once
// Checks of a run's inputs and option values that must pass before any output is written: option
// values (lengths, periods, starts), outages inside the data, GNSS epochs inside the IMU span,
// reference coverage of the outages, and the length of the lab static record used for grafting.
// Each check throws std::runtime_error naming the option, file or key and the value, or returns
// warnings (printable lines) for conditions that still give finite, meaningful results.
#include <optional>
#include <string>
#include <vector>

#include "graftnav/eval/outage_schedule.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct InputCheckOptions {
  // Fewer GNSS epochs than this inside the IMU span (or used by the estimator) is an error unless
  // the run is free-inertial on purpose: with a handful of fixes the filter's position, velocity and
  // heading have not converged when the first outage starts, so outage drift would measure the
  // initialisation, not the IMU. 10 epochs = 10 s of 1 Hz GNSS: a stated floor that catches the
  // "0 or 1 fix" runs, not a convergence criterion (that depends on motion and grade).
  int min_gnss_epochs = 10;
  // Lab static record used for grafting (the basic error signal, tiled forward, reversed, forward,
  // ... over the field test): below lab_static_floor_s it is an error. 60 s = the seed's outage
  // length: a shorter record repeats inside one outage, so the outage drift is built from copies
  // of a few seconds of noise and the record's noise mean (Eq. 12, D = sigma_RW / sqrt(t)) comes
  // back in every tile as a bias. A record shorter than the run's outage spacing (start to start)
  // is a warning (checkLabStaticRecord): consecutive outages then draw overlapping stretches of
  // the same noise, so the RMS over outages counts it more than once.
  double lab_static_floor_s = 60.0;
  void validate() const;  // throws std::invalid_argument naming the field
};

// After buildOutageWindows: a schedule that was asked for but has no window inside the data span
// [t_begin_s, t_end_s] is an error naming the start, length and span.
void requireOutagesInsideData(const OutageScheduleConfig& config,
                              const std::vector<TimeWindow>& windows, double t_begin_s,
                              double t_end_s);

// GNSS epochs inside the IMU span. None, or fewer than options.min_gnss_epochs: an error naming the
// file and both spans, unless free_inertial (then a warning). Returns warnings.
std::vector<std::string> checkGnssCoverage(const GnssSeries& gnss, const std::string& gnss_path,
                                           const ImuSeries& imu, bool free_inertial,
                                           const InputCheckOptions& options = {});
// The same from counts, for GNSS read one epoch at a time: add() each epoch's time in order.
struct GnssCoverage {
  double imu_t0_s = 0.0, imu_t1_s = 0.0;  // the IMU span (imuBegin, last sample's end)
  long total = 0, inside = 0;
  double first_t_s = 0.0, last_t_s = 0.0;
  void add(double t_s);
};
std::vector<std::string> checkGnssCoverage(const GnssCoverage& coverage,
                                           const std::string& gnss_path, bool free_inertial,
                                           const InputCheckOptions& options = {});
// After the run: the number of GNSS epochs the estimator used, same rule.
std::vector<std::string> checkGnssUsed(int gnss_used, bool free_inertial,
                                       const InputCheckOptions& options = {});

// The reference (truth.nav or a reference solution) must hold epochs inside every outage window
// (else the outage statistics cannot be computed: an error naming the file, its span and the
// window); covering only part of the IMU span is a warning. No check when `reference` is empty.
std::vector<std::string> checkReferenceCoverage(const NavSeries& reference,
                                                const std::string& reference_path,
                                                const ImuSeries& imu,
                                                const std::vector<TimeWindow>& outages);

// Length of the lab static record: an error below options.lab_static_floor_s, a warning below
// `outage_spacing_s` (the largest start-to-start spacing of the run's outages; 0: none). Returns
// the warnings.
std::vector<std::string> checkLabStaticRecord(double record_s, const std::string& path,
                                              double outage_spacing_s,
                                              const InputCheckOptions& options = {});
// The largest start-to-start spacing of consecutive windows (the length for a single window; 0 for none).
double outageSpacing(const std::vector<TimeWindow>& windows);

}  // namespace graftnav
