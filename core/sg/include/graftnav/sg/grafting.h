#pragma once
// Signal grafting (Niu et al. 2016, Sec. 2.3): errors of a tested IMU, measured only in the lab,
// are added to the signals of a reference IMU recorded in the field.
//
//   SG#1 (basic-error strategy):  y = x_ref + e_basic
//   SG#2 (full-error strategy):   y = x_ref + d(x_ref) + e_basic
//
// x_ref are the reference IMU's mean rates / specific forces over each sample interval, e_basic
// the basic error signal (lab static output minus its theoretical value, seed Eq. 13-20), and
// d(x) the dynamic error from the lab fitting functions (seed Eq. 21) with their constant term
// taken relative to the lab static point x_s (gravity and Earth rate at the static attitude),
// because e_basic already holds the bias AND the dynamic error at x_s:
//   D_i(x) = p_i(x_i) - x_i + sum_{j != i} M_ij x_j,   d(x) = D(x) - D(x_s)
// p_i is the per-axis polynomial fitted from theoretical to measured output; the off-diagonal of
// the calibration matrix M carries the cross-axis terms (non-orthogonality) that a per-axis
// polynomial cannot see. The reference IMU's own errors stay in x_ref: they are grafted too, and
// their size relative to the tested IMU's is reported by referenceResidualFraction().
//
// The lab static record is usually shorter than the field test. It is extended by mirrored
// tiling: record, record reversed in time, record, ... The tiled signal is continuous at every
// seam (its slow components - bias, bias instability, temperature drift - do not jump) and keeps
// the record's noise spectrum and Allan deviation up to times of the record length. Increments
// over any field interval are exact integrals of the tiled rate signal, so the lab and field
// sampling rates may differ.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "graftnav/imu/imu_profile.h"
#include "graftnav/io/record_spool.h"
#include "graftnav/sg/noise_surrogate.h"
#include "graftnav/sg/power_on_errors.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// Per-sensor dynamic model of SG#2.
struct SensorDynamicFit {
  // poly[i]: coefficients of measured_i = sum_k poly[i][k] * true_i^k, lowest order first (SI).
  std::array<std::vector<double>, 3> poly{
      std::vector<double>{0.0, 1.0}, std::vector<double>{0.0, 1.0}, std::vector<double>{0.0, 1.0}};
  // Calibration matrix (measured = M true + bias); only its off-diagonal is used here.
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  bool use_cross_axis = true;
  // The theoretical output during the lab static record (f_b or omega_ie_b at the static
  // attitude): the basic error signal already carries the dynamic error there.
  Eigen::Vector3d static_point = Eigen::Vector3d::Zero();

  // The dynamic error d(x) = D(x) - D(static_point) (SI, same unit as x).
  Eigen::Vector3d dynamicError(const Eigen::Vector3d& x) const;
};

// The basic error signal: error rates (gyro rad/s, accel m/s^2) of the lab static record,
// extended to any length by mirrored tiling, integrated exactly over requested intervals.
//
// Its samples are held, or (a surrogate made by phaseRandomizedSpooled) kept in an unlinked
// spool and read back in windows of kWindow samples: the spooled signal holds its checkpoints
// (7 bytes per sample) and one window instead of 56 bytes per sample, and gives the same values
// bit for bit. A spooled signal moves its window as it is read, so one thread at a time reads it
// (a copy has a window of its own); a held one may be read from any number of threads.
class BasicErrorSignal {
 public:
  // error_increments: static lab output minus theoretical output, as increments (rad, m/s) with
  // their own t_s/dt_s (uniform or not).
  explicit BasicErrorSignal(const ImuSeries& error_increments);

  double recordLength_s() const { return record_length_s_; }
  std::size_t sampleCount() const { return count_; }
  bool spooled() const { return spool_ != nullptr; }
  // Start of lab sample j, seconds from the beginning of the record (0 for j = 0).
  double sampleStart_s(std::size_t j) const { return j == 0 ? 0.0 : tauEnd(j - 1); }
  // Mean error rates over the whole record (the basic biases): gyro (rad/s), accel (m/s^2).
  Eigen::Vector3d meanGyro_rad_s() const;
  Eigen::Vector3d meanAccel_m_s2() const;

  // Integral of the tiled error rates over (u0, u1], u measured in seconds from the tiling origin.
  // Returns [dtheta (rad); dvel (m/s)].
  Eigen::Matrix<double, 6, 1> integral(double u0_s, double u1_s) const;
  // The last lab-sample boundary at or before u_s in the tiled record (forward tiles: the record's
  // sample starts; mirrored tiles: the same boundaries read backwards). Grafting from a boundary
  // gives each field interval whole lab samples when the rates are equal.
  double sampleBoundaryAtOrBefore(double u_s) const;
  // The record as rates per lab sample with their lengths.
  LabErrorRates rates() const;
  // An independent realization of the record's noise with its mean and spectrum
  // (sg/noise_surrogate.h), as a basic error signal of about twice the record's length.
  // With `slow`, its content slower than slow->slow_period_s is a fresh draw of that model.
  BasicErrorSignal phaseRandomized(std::uint64_t seed, const SlowNoiseModel* slow = nullptr) const;
  // The same surrogate written to an unlinked spool in `spool_directory` (TMPDIR when empty) as
  // its transforms come, channel by channel: neither it nor a copy of it is ever held whole.
  BasicErrorSignal phaseRandomizedSpooled(std::uint64_t seed, const SlowNoiseModel* slow,
                                          const std::string& spool_directory = {}) const;

  static constexpr std::size_t kWindow = 4096;  // samples per read of a spooled signal

 private:
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  BasicErrorSignal() = default;
  std::vector<double> sampleLengths() const;  // per sample, as rates() gives them
  void addCheckpoints();                      // the running sums every kBlock samples
  // Sample j's increment and length (a spooled signal first reads the window holding j).
  const Vec6& inc(std::size_t j) const {
    if (j - window_begin_ >= inc_.size()) readWindow(j);
    return inc_[j - window_begin_];
  }
  double dt(std::size_t j) const {
    if (j - window_begin_ >= dt_.size()) readWindow(j);
    return dt_[j - window_begin_];
  }
  void readWindow(std::size_t j) const;
  Vec6 cumulative(double u_s) const;                  // integral over (0, u], u >= 0
  Vec6 withinRecord(double tau_s) const;              // 0 <= tau <= T
  double tauEnd(std::size_t j) const;                 // end of sample j, from 0
  std::size_t firstEndAtOrAfter(double tau_s) const;  // lower_bound over the sample ends
  std::size_t firstEndAfter(double tau_s) const;      // upper_bound over the sample ends

  // Per lab sample its increment and its length; the running sums of both (sample ends, the
  // cumulative integral) are kept every kBlock samples and summed up from there in the same order
  // as one running sum over the record, so every value is bit for bit what stored running sums
  // hold, at 56 bytes per sample instead of 104.
  static constexpr std::size_t kBlock = 8;
  static_assert(kWindow % kBlock == 0, "a window holds whole checkpoint blocks");
  std::size_t count_ = 0;
  // Samples [window_begin_, window_begin_ + inc_.size()): all of them when held, one window of
  // the spool when spooled (its columns: six of increments, then the lengths).
  mutable std::vector<Vec6> inc_;
  mutable std::vector<double> dt_;
  mutable std::size_t window_begin_ = 0;
  std::shared_ptr<const RecordSpool> spool_;
  std::vector<Vec6> block_cum_;    // integral before sample b * kBlock
  std::vector<double> block_tau_;  // time before sample b * kBlock
  Vec6 total_ = Vec6::Zero();
  double record_length_s_ = 0.0;
};

struct GraftOptions {
  // Where in the tiled lab record the field test starts (s). Chosen from `seed` when negative:
  // the start of a lab sample drawn uniformly from the record, so that different seeds give
  // different but reproducible realizations of the lab noise. A sample boundary matters: with
  // equal lab and field rates each field interval then takes exactly one lab sample; a
  // fractional start would average two neighbours and lower the grafted per-sample noise (by up
  // to 1/sqrt(2), 26 % on average) while keeping its random walk.
  double start_offset_s = -1.0;
  std::uint64_t seed = 1;
  // Turn-on bias change and bias wander of one power-on (zero: the seed's grafting).
  PowerOnErrors power_on;
  // When set, graft a phase-randomized surrogate of the record drawn with this seed instead of
  // the record itself (a new lab-noise realization when the record is too short to give each
  // realization its own segment); start_offset_s then applies to the surrogate.
  std::optional<std::uint64_t> surrogate_seed;
  // With surrogate_seed: the tested IMU's noise model for the surrogate's slow content.
  std::optional<SlowNoiseModel> surrogate_slow_noise;
  // With surrogate_seed: keep the surrogate in a spool in spool_directory (TMPDIR when empty)
  // instead of holding it (about twice the record's samples at 56 bytes each); same values.
  bool spool_surrogate = false;
  std::string spool_directory;
};

// Resolves GraftOptions::start_offset_s (deterministic for a given seed).
double graftStartOffset(const GraftOptions& opt, const BasicErrorSignal& basic);

// The error signal of one grafted realization: the lab record, or its phase-randomized surrogate
// (built here once, when GraftOptions::surrogate_seed is set), where the field test starts in its
// tiling, and the power-on errors. It grafts any block of the reference IMU, so that a recording
// is grafted as it is read: the samples equal graftBasic's / graftFull's on the whole series.
class GraftSignal {
 public:
  // `record` must outlive the signal.
  GraftSignal(const BasicErrorSignal& record, const GraftOptions& opt);
  GraftSignal(const GraftSignal&) = delete;
  GraftSignal& operator=(const GraftSignal&) = delete;
  // Replaces *out with `ref` grafted: SG#1 without fitting functions, SG#2 with both. t0_s is the
  // start of the whole recording's first interval (first sample's t_s - dt_s), the tiling clock's
  // origin.
  void graft(const ImuSeries& ref, double t0_s, const SensorDynamicFit* gyro,
             const SensorDynamicFit* accel, ImuSeries* out) const;
  double startOffset_s() const { return offset_s_; }

 private:
  std::optional<BasicErrorSignal> surrogate_;
  mutable std::mutex read_mutex_;  // a spooled surrogate is read by one graft() at a time
  const BasicErrorSignal* basic_ = nullptr;
  double offset_s_ = 0.0;
  PowerOnErrors power_on_;
};

// SG#1: reference increments plus the basic error signal.
ImuSeries graftBasic(const ImuSeries& ref, const BasicErrorSignal& basic, const GraftOptions& opt);

// SG#2: reference increments plus the dynamic errors of the fitting functions plus the basic
// error signal.
ImuSeries graftFull(const ImuSeries& ref, const BasicErrorSignal& basic,
                    const SensorDynamicFit& gyro, const SensorDynamicFit& accel,
                    const GraftOptions& opt);

// Ratio of the reference IMU's white-noise densities to the tested IMU's, per sensor
// ([gyro, accel]); the share of grafted white noise that is the reference IMU's own.
Eigen::Vector2d referenceResidualFraction(const ImuProfile& reference, const ImuProfile& tested);

}  // namespace graftnav
