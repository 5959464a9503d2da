#pragma once
// Parameters of the individual IMU error terms, all in SI units. Each struct is one physical
// effect; its name and field names are the effect names and parameter keys of diagnosis.json
// so a parsed effect maps one-to-one onto a member of ImuErrorModel.
// Every term is off when its parameters are zero (the defaults).
//
// Notation: x = true mean input over a sample interval (gyro: omega rad/s; accel: specific
// force m/s^2), y = sensor output before noise and quantization, T = sensor temperature (degC).
// "unit" below means rad/s for a gyro term and m/s^2 for an accelerometer term.

#include <Eigen/Core>
#include <string>

#include "graftnav/imu/gauss_markov.h"

namespace graftnav {

// constant_bias: fixed offset of the zero (turn-on bias). y += b.  [unit]
struct ConstantBias {
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  bool isActive() const { return (b.array() != 0.0).any(); }
};

// scale_factor: gain error of each axis (S = diag(k) of seed Eq. 1-2). y += diag(k) x.  [fraction]
struct ScaleFactor {
  Eigen::Vector3d k = Eigen::Vector3d::Zero();
  bool isActive() const { return (k.array() != 0.0).any(); }
};

// non_orthogonality: axes not mutually perpendicular / cross-coupling (N of seed Eq. 1-2,
// off-diagonal only; the diagonal must be zero because it is the scale factor). y += N x.  [rad]
struct NonOrthogonality {
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  bool isActive() const { return (N.array() != 0.0).any(); }
};

// scale_asymmetry: different gain for positive and negative inputs (e.g. closed-loop rebalance
// asymmetry). Per axis, in addition to k: y_i += k_pos_i x_i if x_i >= 0, else k_neg_i x_i.
// [fraction]
struct ScaleAsymmetry {
  Eigen::Vector3d k_pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d k_neg = Eigen::Vector3d::Zero();
  bool isActive() const { return (k_pos.array() != 0.0).any() || (k_neg.array() != 0.0).any(); }
};

// scale_nonlinearity: quadratic departure from a straight input-output line, y = x + k2 x^2.
// Per axis: y_i += k2_i x_i^2.  [1/unit]
struct ScaleNonlinearity {
  Eigen::Vector3d k2 = Eigen::Vector3d::Zero();
  bool isActive() const { return (k2.array() != 0.0).any(); }
};

// temperature_bias: bias drifting linearly with sensor temperature.
// y += per_degC (T - t_ref_degC).  [unit/degC]. t_ref_degC is also the reference of
// TemperatureScale of the same sensor.
struct TemperatureBias {
  Eigen::Vector3d per_degC = Eigen::Vector3d::Zero();
  double t_ref_degC = 25.0;
  bool isActive() const { return (per_degC.array() != 0.0).any(); }
};

// temperature_scale: gain drifting linearly with sensor temperature.
// y_i += per_degC_i (T - t_ref_degC) x_i (t_ref_degC of the sensor's TemperatureBias).
// [fraction/degC]
struct TemperatureScale {
  Eigen::Vector3d per_degC = Eigen::Vector3d::Zero();
  bool isActive() const { return (per_degC.array() != 0.0).any(); }
};

// bias_instability: slowly wandering bias (flicker floor of the Allan deviation) modelled as a
// first-order Gauss-Markov process, GaussMarkovParams{sigma [unit], tau_s [s]}.
using BiasInstability = GaussMarkovParams;

// white_noise: wide-band sensor noise, angle random walk (gyro, rad/sqrt(s)) or velocity random
// walk (accel, m/s/sqrt(s)). An increment over dt gets N(0, (density sqrt(dt))^2) per axis, so
// the mean rate over T seconds has standard deviation density / sqrt(T) (seed Eq. 12).
struct WhiteNoise {
  Eigen::Vector3d density = Eigen::Vector3d::Zero();  // [unit sqrt(s)] = [unit * s / sqrt(s)]
  bool isActive() const { return (density.array() != 0.0).any(); }
};

// bias_random_walk: bias diffusing without bound (rate random walk for a gyro, acceleration
// random walk for an accelerometer): b_{k+1} = b_k + N(0, density^2 dt), b_0 = 0.
// [unit/sqrt(s)]
struct BiasRandomWalk {
  Eigen::Vector3d density = Eigen::Vector3d::Zero();
  bool isActive() const { return (density.array() != 0.0).any(); }
};

// vibration_rectification: vibration turned into a bias by non-linear or asymmetric sensor
// response (pendulous accelerometers, Coriolis-vibratory gyros). y += coeff r, where r is the
// named regressor computed by VibrationRegressor below.
// coeff [unit per regressor unit, e.g. m/s^2 per (m/s^2)^2 or rad/s per (m/s^2)^2].
struct VibrationRectification {
  Eigen::Vector3d coeff = Eigen::Vector3d::Zero();
  // "specific_force_hp_sq": short-window mean of |high-passed specific force|^2 [(m/s^2)^2];
  // "angular_rate_hp_sq":   the same for the angular rate [(rad/s)^2].
  std::string regressor = "specific_force_hp_sq";
  double window_s = 1.0;  // time constant of the high-pass and of the averaging (s), > 0
  bool isActive() const { return (coeff.array() != 0.0).any(); }
};

// quantization: the output increments are whole multiples of step; the remainder is carried to
// the next sample (as a real IMU's pulse counter does), so the cumulative sum of the output never
// differs from the cumulative sum of the unquantized increments by more than step / 2.
// step [rad or m/s per increment]
struct Quantization {
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  bool isActive() const { return (step.array() != 0.0).any(); }
};

// g_sensitivity (gyro only): gyro bias caused by specific force (mass unbalance / acceleration
// sensitivity of the proof mass). omega_y += G f, G row-major 3x3.  [rad/s per m/s^2]
struct GSensitivity {
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
  bool isActive() const { return (G.array() != 0.0).any(); }
};

// time_offset: the tested IMU's time tags are late by tau_s: the sample tagged t was measured at
// t - tau_s (positive = late tags). Applied by integral-preserving interpolation. [s]
struct TimeOffset {
  double tau_s = 0.0;
  bool isActive() const { return tau_s != 0.0; }
};

// lever_arm (size effect): the tested IMU sits at r_m from the reference IMU (reference body
// frame, FRD) and so feels the extra specific force of a rotating rigid body:
// f_t = f + omega_dot x r + omega x (omega x r).  [m]
struct LeverArm {
  Eigen::Vector3d r_m = Eigen::Vector3d::Zero();
  bool isActive() const { return (r_m.array() != 0.0).any(); }
};

// mounting_misalignment: the tested body frame t is rotated from the reference body frame b by
// the small rotation vector rotation_rad (rotation of t relative to b, the same convention as
// q_nb: C_bt = exp(rotation_rad)), so the tested IMU measures omega_t = C_tb omega,
// f_t = C_tb f with C_tb = C_bt^T ~ I - skew(rotation_rad).  [rad]
struct MountingMisalignment {
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();
  bool isActive() const { return (rotation_rad.array() != 0.0).any(); }
};

// Computes a vibration_rectification regressor sample by sample from the true mean input of each
// interval (no allocation). With a = 1 - exp(-dt / window_s):
//   lp_k = lp_{k-1} + a (x_k - lp_{k-1})   (lp_0 = x_0)   first-order low-pass
//   hp_k = x_k - lp_k                                      high-passed input
//   r_k  = r_{k-1} + a (|hp_k|^2 - r_{k-1})  (r_0 = 0)     short-window mean square
// x is the specific force (m/s^2) or the angular rate (rad/s), depending on the regressor name.
// Fitting code should compute the regressor with this class from the same signal.
class VibrationRegressor {
 public:
  explicit VibrationRegressor(double window_s = 1.0);
  // True for the regressor names listed in VibrationRectification.
  static bool isKnownName(const std::string& name);
  // Whether the named regressor is built from the angular rate (else from specific force).
  static bool usesAngularRate(const std::string& name);
  void reset();
  // Feeds the mean input of one interval of length dt_s; returns r_k.
  double update(const Eigen::Vector3d& x, double dt_s);
  double value() const { return r_; }

 private:
  double window_s_;
  Eigen::Vector3d lp_ = Eigen::Vector3d::Zero();
  double r_ = 0.0;
  bool started_ = false;
};

}  // namespace graftnav
