#pragma once
// Loosely coupled, closed-loop GNSS/INS error-state EKF (seed section 2.4, Eq. 22, 23, 26, 27)
// on the 21-state psi-angle model of ins_error_model.h, and the run over an EstimationProblem.
//
// Per IMU sample: the raw increments are corrected with the current bias/scale estimates and
// mechanized by core's Strapdown. The covariance is propagated every covariance_interval_s with
// F evaluated at the current state and the mean corrected rate/specific force of the interval.
// A GNSS fix inside an IMU interval splits that sample (uniform-rate assumption) so the update
// happens exactly at the GNSS time. Update: chi-square gate on the innovation, Joseph form,
// symmetrized covariance, then the estimate is fed back (PVA reset, sensor estimates augmented)
// and the error state is zero again.
//
// Vehicle aiding (problem.aiding, graftnav/estimation/vehicle_aiding.h): every 1/rateHz() s, at
// the end of the IMU sample that reaches that time, a vehicle-frame velocity update with the
// odometer's forward speed (interpolated there) and NHC's lateral and vertical rows
// (vehicle_velocity.h), gated at gate_probability like GNSS. When the odometer scale factor is
// estimated it is a 22nd state, kept beside the 21-state covariance as its cross-covariance
// column and variance: the 21-state propagation is untouched and a run without it computes
// exactly what it did before the state existed.

#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "graftnav/nav/mechanization.h"
#include "graftnav/estimation/ekf_options.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/estimation/usable_gnss.h"
#include "graftnav/filters/ins_error_model.h"
#include "graftnav/estimation/solution_sink.h"
#include "graftnav/filters/vehicle_velocity.h"

namespace graftnav {

// The odometer scale factor k as the 22nd state (vehicle_aiding.h): its estimate, and its
// covariance with the 21-state error (P_xk) and its variance (P_kk). Its transition is 1 (a
// random walk), so the 21-state propagation leaves it alone: P_xk <- Phi P_xk,
// P_kk <- P_kk + q dt.
struct OdometerScaleState {
  double k = 0.0;
  ErrorState P_xk = ErrorState::Zero();
  double P_kk = 0.0;
  double q_per_s = 0.0;  // random-walk variance per second
};

// What the RTS smoother needs at one record epoch of the forward pass.
struct SmootherRecord {
  double t_s = 0.0;
  NavState nav;                         // nominal state after the feedback at this epoch
  ImuErrorEstimate sensors;             // sensor estimates after the feedback
  ErrorState dx = ErrorState::Zero();   // correction fed back here (zero without an update)
  ErrorCov P_prior = ErrorCov::Zero();  // before the update at t_s
  ErrorCov P_post = ErrorCov::Zero();   // after it
  ErrorCov Phi = ErrorCov::Identity();  // transition from the previous record to this one
  // With the odometer scale state: its part of the same (P_xk, P_kk of the prior and the
  // posterior, the estimate after the feedback and the correction fed back).
  bool has_scale = false;
  OdometerScaleState scale_prior, scale_post;
  double dk = 0.0;
};

// A deque: records are ~10 KB each and an hour holds thousands; growing a vector would hold
// the old and the new copy at once.
using SmootherRecords = std::deque<SmootherRecord>;

class GnssInsEkf {
 public:
  GnssInsEkf(const NavState& initial, const ErrorCov& P0, const ImuProfile& profile,
             const EkfOptions& options);

  // Mechanizes one raw sample (any interval length) and propagates the covariance when the
  // accumulated interval reaches covariance_interval_s.
  void propagate(const ImuSample& raw);
  // Propagates the covariance over the interval accumulated so far (no-op if empty).
  void flushCovariance();

  // GNSS position update at the antenna; returns false when the fix fails the gate.
  bool updatePosition(const GnssFix& fix, const Eigen::Vector3d& lever_arm_b_m);
  // GNSS velocity update at the antenna (NED, m/s, 1-sigma per axis).
  bool updateVelocity(const Eigen::Vector3d& v_ned_m_s, const Eigen::Vector3d& std_m_s,
                      const Eigen::Vector3d& lever_arm_b_m);

  // Adds the odometer scale factor as a state with initial 1-sigma sigma0 and random walk
  // (fraction/sqrt(s)); before any update.
  void enableOdometerScale(double sigma0, double random_walk_per_sqrt_s);
  bool estimatesOdometerScale() const { return has_scale_; }
  const OdometerScaleState& odometerScale() const { return scale_; }
  // Vehicle-frame velocity update (vehicle_velocity.h): the rows whose row_std_m_s is > 0, the
  // forward one only with an odometer speed (speed_m_s not null). Returns false when gated out
  // (or when no row is left).
  bool updateVehicleVelocity(const VehicleGeometry& g, const Eigen::Vector3d& row_std_m_s,
                             const double* speed_m_s);
  int vehicleUsed() const { return vehicle_gate_.used; }
  int vehicleRejected() const { return vehicle_gate_.rejected; }

  const NavState& state() const { return nav_; }
  const ImuErrorEstimate& sensors() const { return sensors_; }
  const ErrorCov& covariance() const { return P_; }
  // 1-sigma of (dr, v error, phi) in the true n frame, from the last propagated covariance.
  const PvaSigma& pvaSigma();
  int rejected() const { return gnss_gate_.rejected; }

  // Records for the smoother (off by default).
  void enableRecording(bool on);
  SmootherRecords& records() { return records_; }
  // Appends a record at the current time (after flushing the covariance).
  void recordNow();

 private:
  // Chi-square gate of one kind of measurement; after max_consecutive rejections in a row the
  // next is accepted (avoids lock-out).
  struct Gate {
    double threshold[4] = {0.0, 0.0, 0.0, 0.0};  // by number of rows
    int consecutive = 0, rejected = 0, used = 0;
  };
  template <int M>
  bool update(const Eigen::Matrix<double, M, 1>& z,
              const Eigen::Matrix<double, M, ekf::kStateDim>& H,
              const Eigen::Matrix<double, M, 1>& r_diag, const Eigen::Matrix<double, M, 1>& H_k,
              Gate& gate);
  template <int M>
  bool updateRows(const Eigen::Vector3d& z, const Eigen::Matrix<double, 3, ekf::kStateDim>& H,
                  const Eigen::Vector3d& r, const Eigen::Vector3d& H_k, const int* rows);
  bool accept(Gate& gate, int rows, double d2);
  void applyCorrection(const ErrorState& dx);
  void pushRecord(const ErrorState& dx, const ErrorCov& P_prior, double dk = 0.0,
                  const OdometerScaleState* scale_prior = nullptr);

  EkfOptions opt_;
  ImuProfile profile_;
  ErrorState qc_;
  Strapdown mech_;
  NavState nav_;
  ImuErrorEstimate sensors_;
  ErrorCov P_;
  // Covariance-interval accumulators.
  Eigen::Vector3d sum_dtheta_ = Eigen::Vector3d::Zero(), sum_dvel_ = Eigen::Vector3d::Zero();
  double acc_dt_ = 0.0;
  Eigen::Vector3d last_omega_b_ = Eigen::Vector3d::Zero();
  // Smoother bookkeeping.
  bool recording_ = false;
  ErrorCov Phi_since_record_ = ErrorCov::Identity();
  double last_record_t_ = 0.0;
  SmootherRecords records_;
  Gate gnss_gate_, vehicle_gate_;
  bool has_scale_ = false;
  OdometerScaleState scale_;
  PvaSigma sigma_;
  bool sigma_valid_ = false;
};

// Initial covariance from the problem (initial_sigma when given) and the IMU profile.
ErrorCov initialCovariance(const EstimationProblem& problem, const EkfOptions& options);

// The portion of `s` inside (t_from, t_to] assuming a uniform rate over the sample.
ImuSample sliceImuSample(const ImuSample& s, double t_from, double t_to);

// The forward EKF run, one IMU sample at a time: GNSS updates at their epochs (a sample that
// straddles a fix is split there), output every output_decimation-th sample into a sink. The
// problem supplies everything but the samples (problem.imu is not read), so the samples may come
// from memory or from a file in blocks; the result is the same either way.
class EkfPass {
 public:
  // Applies the fixes at (or before, within 1 us) the initial time. With `record`, the forward
  // pass is recorded for the smoother. The problem must outlive the pass (its fixes are read
  // one at a time as the samples come).
  EkfPass(const EstimationProblem& problem, const EkfOptions& options, bool record);
  // Processes the next sample (times increasing); samples not after the current time are skipped.
  // `sink` (may be null) receives the output epochs.
  void add(const ImuSample& sample, SolutionSink* sink);
  // Closes the pass: throws std::invalid_argument when no sample came after the initial time;
  // returns the GNSS bookkeeping (no states; the fixes after the last sample read to count the
  // withheld ones) and moves the records into *records when given.
  NavSolution finish(SmootherRecords* records = nullptr);

 private:
  // Applies the next usable fix and moves past it.
  void applyNextFix();
  // The vehicle-frame velocity update at t_s when one is due.
  void aidVehicle(double t_s);

  EkfOptions options_;
  UsableGnss gnss_;  // the problem's fixes, one at a time, outages withheld
  Eigen::Vector3d lever_arm_b_m_;
  int gnss_week_ = 0;
  GnssInsEkf filter_;
  NavSolution bookkeeping_;
  double t_cur_ = 0.0;
  std::size_t processed_ = 0;
  // Vehicle aiding (off when aiding_.any() is false).
  VehicleAidingOptions aiding_;
  VehicleGeometry vehicle_;
  std::unique_ptr<OdometerInterpolator> odometer_;
  double t0_ = 0.0;
  long next_aid_ = 1;  // the next update is due at t0_ + next_aid_ / aiding_.rateHz()
};

// ImuBlockFn, ImuPassFn: graftnav/estimation/nav_solution.h.

// The forward EKF with the samples from `imu` (problem.imu is not read) and the output epochs
// given to `sink`: memory does not depend on the recording's length. Returns the GNSS
// bookkeeping (no states); the epochs equal runEkf's for the same samples.
NavSolution runEkfStreaming(const EstimationProblem& problem, const EkfOptions& options,
                            const ImuPassFn& imu, SolutionSink& sink);

// Forward EKF over the problem's samples (an EkfPass). With `records`, the forward pass is
// recorded for the smoother. keep_states = false returns only the GNSS bookkeeping (the
// smoother's forward pass).
NavSolution runEkf(const EstimationProblem& problem, const EkfOptions& options,
                   SmootherRecords* records = nullptr, const ProgressFn& progress = {},
                   bool keep_states = true);

}  // namespace graftnav
