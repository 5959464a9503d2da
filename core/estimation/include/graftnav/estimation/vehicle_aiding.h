#pragma once
// Land-vehicle aiding shared by every estimator: a wheel odometer's forward speed and the
// non-holonomic constraint (NHC: the vehicle neither slides sideways nor leaves the road), both
// measurements of one vector, the vehicle-frame velocity.
//
// Frames: b the IMU body (FRD), n local-level NED, v the vehicle (forward-right-down: x the
// direction the wheels roll, z down through the floor). The IMU's mounting angles are the
// roll, pitch and yaw (ZYX, as an attitude) of b relative to v, so C_vb = C(roll, pitch, yaw)
// turns body vectors into vehicle vectors (OB_GINS's `bodyangle`). The odometer and the NHC
// refer to the point at lever arm l_b from the IMU (body FRD), ideally the rear axle's centre.
// Its velocity relative to the Earth, in v:
//
//   v_v = C_vb (C_bn v_n + omega_nb_b x l_b),   omega_nb_b = omega_ib_b - C_bn omega_in_n
//
// The odometer measures s = (1 + k) v_v.x + noise: k is its scale error, a multiplicative error
// of the measured speed (+3000 ppm reads 0.3 % fast), estimated as a random walk from a stated
// initial sigma. NHC measures v_v.y = v_v.z = 0 with its 1-sigma. With both on, one update
// carries the forward row with the odometer's std and the lateral and vertical rows with NHC's.
// (The factor graphs, which keep their velocity in an Earth-fixed frame, use the body rate
// relative to the Earth; it differs from omega_nb_b by the transport rate, ~v/R: below 1e-5 m/s
// at a lever arm of metres.)

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

namespace graftnav {

// One line of field/odometer.txt: forward speed at the odometer, m/s, at GNSS seconds of week.
struct OdometerSample {
  double t_s = 0.0;
  double speed_m_s = 0.0;
};
using OdometerSeries = std::vector<OdometerSample>;

// Odometer samples one at a time, in time order (a file read as the run goes, or a series).
class OdometerSource {
 public:
  virtual ~OdometerSource() = default;
  virtual bool next(OdometerSample* sample) = 0;  // false at the end
};
using OdometerOpenFn = std::function<std::unique_ptr<OdometerSource>()>;
// A pass over a series held elsewhere (`samples` must outlive the source).
std::unique_ptr<OdometerSource> seriesOdometerSource(const OdometerSeries& samples);

// The odometer scale factor k (fraction: +0.003 reads 0.3 % fast) and its 1-sigma at an epoch
// (NaN when the estimator gives none).
struct OdometerScaleEstimate {
  double scale = 0.0;
  double std = 0.0;
};

struct OdometerOptions {
  bool enabled = false;
  // 1-sigma of the vehicle-frame velocity the odometer gives, forward, lateral, vertical (m/s).
  // Lateral and vertical <= 0: the odometer gives the forward speed only; > 0: it also says the
  // wheels do not slide (OB_GINS's odometer, whose std has all three).
  Eigen::Vector3d std_m_s = Eigen::Vector3d(0.05, 0.0, 0.0);
  double scale_std = 0.01;                    // initial 1-sigma of k (fraction); 0: k = 0 known
  double scale_random_walk_per_sqrt_s = 0.0;  // random walk of k (fraction/sqrt(s))
  Eigen::Vector3d lever_arm_b_m = Eigen::Vector3d::Zero();  // odometer point from the IMU, FRD
  Eigen::Vector3d mounting_rad = Eigen::Vector3d::Zero();   // roll, pitch, yaw of b in v
  double rate_hz = 10.0;  // EKF/RTS update rate (speed interpolated from the samples)
  // Largest interval between two samples across which the speed is interpolated; a wider gap
  // gives no odometer measurement inside it.
  double max_gap_s = 0.5;
  bool estimatesScale() const { return enabled && scale_std > 0.0; }
};

struct NhcOptions {
  bool enabled = false;
  Eigen::Vector2d std_m_s = Eigen::Vector2d(0.1, 0.1);  // lateral, vertical (m/s)
  double rate_hz = 10.0;                                // EKF/RTS update rate
};

struct VehicleAidingOptions {
  OdometerOptions odometer;
  NhcOptions nhc;  // applied at the odometer's lever arm and mounting angles

  bool any() const { return odometer.enabled || nhc.enabled; }
  // Rotation from the IMU body to the vehicle frame (the mounting angles).
  Eigen::Matrix3d C_vb() const;
  // Update rate of the filters: the larger of the enabled sections' rates.
  double rateHz() const;
  // 1-sigma of the rows [forward, lateral, vertical] of one update (<= 0: row not measured; the
  // forward row needs an odometer sample there, which the caller checks).
  Eigen::Vector3d rowStd_m_s() const;
  // Throws std::invalid_argument naming the field ("odometer.std_m_s ...") on a bad value.
  void validate() const;
};

// The forward speed at increasing times from a one-pass source, interpolated linearly between
// the two samples around each time; none where they are more than max_gap_s apart or outside
// the samples. Holds two samples.
class OdometerInterpolator {
 public:
  OdometerInterpolator(std::unique_ptr<OdometerSource> source, double max_gap_s);
  // Speed at t_s (non-decreasing from call to call) into *speed_m_s; false when there is none.
  // Throws std::invalid_argument naming both times when a sample is earlier than the one before.
  bool at(double t_s, double* speed_m_s);

 private:
  bool advance();
  std::unique_ptr<OdometerSource> source_;
  double max_gap_s_;
  OdometerSample a_, b_;
  bool has_a_ = false, has_b_ = false, ended_ = false;
};

}  // namespace graftnav
