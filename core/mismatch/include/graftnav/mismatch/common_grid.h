#pragma once
// Common time base of the mismatch finder: two IMU records with different rates and sample
// phases are compared on one grid of averaging bins. Each record's increments are summed into a
// cumulative integral Theta(t) (exact at the sample boundaries, a cubic Hermite curve between
// them, see CumulativeImu::at), and the mean rate over a bin (a, b] is
// (Theta(b) - Theta(a)) / (b - a). Nothing is filtered or resampled twice, different rates
// (100 vs 120 Hz) and sample phases are handled, and a time shift is a shift of a and b.

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "graftnav/io/imu_recording.h"
#include "graftnav/nav/types.h"

namespace graftnav {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// A per-sample map applied as a record is read, in place of a mapped copy of the record (e.g. the
// tested IMU's lab-calibrated response to the reference's inputs, or |x| of each sample). It must
// keep t_s, dt_s and the temperature. Empty: the samples as they are.
using ImuSampleMap = std::function<ImuSample(const ImuSample&)>;

// Cumulative integral of an IMU record: [angle (rad); velocity (m/s)] since the start of the
// first sample, and the integral of temperature (degC s) when every sample has one.
class CumulativeImu {
 public:
  // Throws std::invalid_argument when the series is empty or a dt_s <= 0 (naming the index).
  explicit CumulativeImu(const ImuSeries& imu, const ImuSampleMap& map = {});

  double beginTime_s() const { return t_.front(); }
  double endTime_s() const { return t_.back(); }
  bool hasTemperature() const { return has_temperature_; }
  // Integral from beginTime_s() to t_s; outside the record the end rates are held. Between the
  // sample boundaries (where it equals the summed increments exactly) it is band limited where
  // the 64 surrounding samples are uniform (Kaiser-windowed sinc on the departure from the
  // chord: 0.3 Hz to 0.84 x Nyquist keep their gain to 1e-5), else a cubic Hermite curve
  // whose node slopes are the 5-point derivative of the cumulative values. A piecewise linear
  // integral (rate constant within a sample) shifts a signal by a fraction of a sample with a
  // low-pass error that the finder read as a scale factor (~0.3 % at 3 Hz, 4 ms); the Hermite
  // curve does the same on 15-40 Hz road vibration (0.4-17 %).
  Vector6d at(double t_s) const;
  double temperatureIntegralAt(double t_s) const;  // NaN when no temperature
  // Derivative of at() (the end rates outside the record).
  Vector6d rateAt(double t_s) const;

 private:
  struct NodeView;  // the arrays as cumulative_nodes.h reads them
  std::size_t segment(double t_s) const;
  void computeIrregular();
  Vector6d slope(std::size_t k) const;  // node slope of the Hermite interpolation at t_[k]
  std::vector<double> t_;      // sample boundaries: t_[0] = start of sample 0, t_[k+1] = end of k
  std::vector<Vector6d> cum_;  // integral at t_[k]
  std::vector<double> cum_temp_;  // temperature integral at t_[k]
  std::vector<int> irregular_;    // prefix count of interval changes (uniform-window test)
  bool has_temperature_ = false;
};

// Bins of equal length bin_s covering [t_begin_s, t_begin_s + count bin_s].
struct GridSpec {
  double t_begin_s = 0.0;
  double bin_s = 0.05;
  int count = 0;
  double binStart(int i) const { return t_begin_s + i * bin_s; }
  double binMid(int i) const { return t_begin_s + (i + 0.5) * bin_s; }
};

// The largest grid inside the overlap of the records, starting margin_s after the later start.
// Throws std::invalid_argument when bin_s <= 0 or the overlap holds fewer than 10 bins.
GridSpec commonGrid(const ImuSeries& a, const ImuSeries& b, double bin_s, double margin_s = 0.0);
// The same from the recordings' first and last samples.
GridSpec commonGrid(const ImuRecording& a, const ImuRecording& b, double bin_s,
                    double margin_s = 0.0);

// Median of the records' sample intervals dt_s (0 for an empty record). The recording's is
// counted over its distinct intervals in one pass (a clock's few, not one per sample).
double medianSampleInterval(const ImuSeries& imu);
double medianSampleInterval(const ImuRecording& imu);

// Bins of `grid` (1 = affected) that overlap a sampling gap of `imu`: a sample whose interval
// dt_s exceeds gap_factor x the median interval (lost samples: the sample after the gap carries
// only its own increment, so a bin's mean rate there is wrong), widened by one bin on each side
// (the integral's node slopes use neighbouring samples). Empty records give no mask.
std::vector<char> binsOverlappingGaps(const ImuSeries& imu, const GridSpec& grid,
                                      double gap_factor = 1.5);

// The same mask made as the samples come (in time order): after medianSampleInterval, one more
// pass feeds add(); what it holds is the mask (one byte a bin).
class GapMask {
 public:
  GapMask(const GridSpec& grid, double median_interval_s, double gap_factor = 1.5);
  void add(const ImuSample& sample);
  void add(const ImuSeries& block) {
    for (const ImuSample& s : block) add(s);
  }
  const std::vector<char>& mask() const { return mask_; }

 private:
  GridSpec grid_;
  double limit_s_ = 0.0;
  std::vector<char> mask_;
};

// Mean rates of one record over the bins of a grid.
struct BinnedImu {
  GridSpec grid;
  Eigen::MatrixX3d omega_rad_s;      // mean angular rate per bin
  Eigen::MatrixX3d f_m_s2;           // mean specific force per bin
  Eigen::VectorXd temperature_degC;  // mean temperature per bin (NaN when absent)
  // Within-bin RMS of the sample specific force about the bin mean (m/s^2): vibration level.
  Eigen::VectorXd f_within_rms_m_s2;
  int size() const { return grid.count; }
  // Row i as [omega; f].
  Vector6d row(int i) const {
    Vector6d r;
    r << omega_rad_s.row(i).transpose(), f_m_s2.row(i).transpose();
    return r;
  }
};

// Bins `imu` on `grid`. time_shift_s re-aligns a record whose tags are late by time_shift_s: bin
// (a, b] of the grid (true time) takes the record's integral over tags (a + shift, b + shift].
// `map`, when given, is applied to every sample first (ImuSampleMap).
BinnedImu binImu(const ImuSeries& imu, const GridSpec& grid, double time_shift_s = 0.0,
                 const ImuSampleMap& map = {});

// Bin means (as binImu, same grid and shift) of even functions of each sample's input, per axis:
// |x| and x^2 of the rates and of the specific force. A sensor bends its input sample by sample:
// under road vibration the bin mean of |x| is not |bin mean| (for a vibration of amplitude A
// about a small x0 it is ~ 2 A / pi + x0^2 / (pi A)), so regressors built from the bin means
// showed an asymmetry partly as a quadratic, and a quadratic partly as vibration rectification.
struct EvenPowerBins {
  Eigen::MatrixX3d abs_omega_rad_s, abs_f_m_s2;  // mean |x| per bin
  Eigen::MatrixX3d sq_omega, sq_f;               // mean x^2 per bin ((rad/s)^2, (m/s^2)^2)
};
EvenPowerBins binEvenPowers(const ImuSeries& imu, const GridSpec& grid, double time_shift_s = 0.0);

}  // namespace graftnav
