#pragma once
// Errors of a navigation solution against a truth or reference series (interpolated in time),
// and the outage statistics of the seed (RMS over all outage epochs, Tables 2-3) and of the peers
// (RMS over outages of the per-outage maximum drift), plus a NEES consistency figure.
// Everything here is SI (m, rad); reports convert to degrees.

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <vector>

#include "graftnav/nav/distributions.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// The five numbers of the seed's tables. Horizontal = sqrt(dN^2 + dE^2), vertical = |dD|.
struct DriftStats {
  double horizontal_m = std::numeric_limits<double>::quiet_NaN();
  double vertical_m = std::numeric_limits<double>::quiet_NaN();
  double roll_rad = std::numeric_limits<double>::quiet_NaN();
  double pitch_rad = std::numeric_limits<double>::quiet_NaN();
  double heading_rad = std::numeric_limits<double>::quiet_NaN();
};

// Solution minus reference at one solution epoch.
struct EpochError {
  double t_s = 0.0;
  Eigen::Vector3d pos_ned_m = Eigen::Vector3d::Zero();     // north, east, down (m)
  Eigen::Vector3d vel_ned_m_s = Eigen::Vector3d::Zero();   // (m/s)
  Eigen::Vector3d euler_rad = Eigen::Vector3d::Zero();     // roll, pitch, heading; wrapped
  Eigen::Vector3d att_n_rad = Eigen::Vector3d::Zero();     // rotation vector of q_sol q_ref^-1 (n)
  double nees = std::numeric_limits<double>::quiet_NaN();  // sum over the 9 PVA of (e/sigma)^2
  int outage = -1;                                         // index into the outages, -1 outside
};

struct OutageDrift {
  TimeWindow window;
  int epochs = 0;  // solution epochs evaluated inside
  DriftStats max;  // maximum of each absolute error inside the window
};

enum class EvaluationEpochs {
  kAuto,       // the epochs of the sparser series (the denser one is interpolated)
  kSolution,   // every solution epoch, the reference interpolated
  kReference,  // every reference epoch, the solution interpolated
};

struct EvaluationOptions {
  // Interpolating a 10 Hz truth to 200 Hz solution epochs turns road vibration (attitude changes
  // of 0.05 deg in 20 ms) into fake errors; kAuto evaluates at the sparser series' epochs.
  EvaluationEpochs epochs = EvaluationEpochs::kAuto;
  // NEES is sampled at most once per this interval: consecutive IMU-rate epochs are strongly
  // correlated, and the chi-square band assumes independent samples (it is still optimistic).
  double nees_interval_s = 1.0;
  double nees_band_probability = 0.95;  // two-sided
  void validate() const;
};

struct Evaluation {
  std::vector<EpochError> epochs;    // the evaluated epochs (empty when streamed: epoch_count)
  std::size_t epoch_count = 0;       // number of evaluated epochs
  DriftStats overall_rms;            // all evaluated epochs
  DriftStats outage_rms;             // seed: RMS over all epochs inside outages
  DriftStats outage_max_rms;         // peers: RMS over outages of the per-outage maximum
  std::vector<OutageDrift> outages;  // one per outage window with at least one epoch
  int outage_epochs = 0;
  // NEES of the 9 PVA error states using the solution's diagonal sigma (an average of
  // sum_i e_i^2 / sigma_i^2, expectation 9 for a consistent estimator).
  double nees_mean = std::numeric_limits<double>::quiet_NaN();
  int nees_dof = 9;
  int nees_samples = 0;
  double nees_band_low = std::numeric_limits<double>::quiet_NaN();
  double nees_band_high = std::numeric_limits<double>::quiet_NaN();
};

// Errors of `solution.states` against `reference` (both sorted by time) at the epochs chosen by
// options.epochs, the other series interpolated (nav_interp.h; sigma linearly); epochs outside
// the other series' span are skipped. Throws std::invalid_argument when the
// two series do not overlap.
Evaluation evaluateSolution(const NavSolution& solution, const NavSeries& reference,
                            const std::vector<TimeWindow>& outages,
                            const EvaluationOptions& options = {});

}  // namespace graftnav
