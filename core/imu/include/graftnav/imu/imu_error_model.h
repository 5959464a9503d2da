#pragma once
// The one composable IMU error model of graftnav, used by the simulator, by grafting and by the
// mismatch finder. Parameters are plain SI values (see imu_error_terms.h for each term's equation
// and physics); a term is off when its parameters are zero, so any subset can be composed.
//
// What a tested IMU outputs, given the ideal increments of the reference IMU (ImuSeries, each
// sample the integral of omega_ib_b and f_b over (t - dt, t]):
//
//  A. Geometry (deterministic, on the whole series; applyGeometry):
//    1. lever_arm: dv += (omega(t_k) - omega(t_{k-1})) x r + integral omega x (omega x r) dt,
//       with the node rates omega(t_k) from the derivative of a 5-point Lagrange polynomial
//       through the cumulative angle, and the integral by 3-point Gauss-Legendre over the
//       quadratic rate consistent with the two node rates and the interval's mean rate.
//    2. mounting_misalignment: dtheta <- C_tb dtheta, dv <- C_tb dv (C_tb = exp(rotation)^T).
//    3. time_offset: output increment k = Theta(t_k - tau) - Theta(t_{k-1} - tau), Theta the
//       cumulative increment, interpolated by cubic Hermite segments through the exact cumulative
//       values with the node rates above as slopes (integrals are preserved: the outputs
//       telescope); beyond the ends the end rate is held. Temperature is interpolated linearly.
//    1 and 3 work on an increment series, so they are exact only for motion that is smooth over a
//    few samples; near Nyquist (road vibration) the node rates lose gain. The case simulator
//    therefore integrates a tested IMU's lever arm and time offset from the trajectory itself
//    (IdealImuOptions::lever_arm_b_m, shifted intervals) and leaves only 2 to this step.
//  B. Sensor (per sample, ImuErrorGenerator; no heap allocation per sample), with x_g = dtheta/dt,
//     x_a = dv/dt the mean inputs after geometry and T the sample temperature:
//    4. vibration regressors updated from x_a (or x_g).
//    5. deterministic error (linear in every parameter, each term acting on the true input):
//       y_g = x_g + b_g + diag(k_g) x_g + N_g x_g + asym_g(x_g) + k2_g.x_g^2
//             + per_degC_b (T - T_ref) + diag(per_degC_s (T - T_ref)) x_g + G x_a + c_g r
//       y_a = the same with the accel parameters and no G term.
//    6. stochastic bias: Gauss-Markov (bias_instability) + bias_random_walk, the state at the
//       sample (propagated exactly over dt from the previous sample).
//    7. increment = dtheta + (y - x + bias) dt + N(0, density^2 dt)   (white_noise)
//    8. quantization with the remainder carried to the next sample.
//  Output samples keep the input's t_s and dt_s.
//
// Randomness (deterministic for a given seed): each stochastic term has its own stream,
// StandardNormalSampler(deriveStreamSeed(seed, id)), ids: gyro white 1, accel white 2,
// gyro bias_instability 3, accel bias_instability 4, gyro bias_random_walk 5, accel random walk 6.
// Switching one term on or off leaves the realization of the others unchanged.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "graftnav/imu/imu_error_terms.h"
#include "graftnav/imu/imu_profile.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// The terms that belong to one sensor triad (gyro or accelerometer). Units: gyro rad/s based,
// accel m/s^2 based (see imu_error_terms.h).
struct SensorErrorTerms {
  ConstantBias constant_bias;
  ScaleFactor scale_factor;
  NonOrthogonality non_orthogonality;
  ScaleAsymmetry scale_asymmetry;
  ScaleNonlinearity scale_nonlinearity;
  TemperatureBias temperature_bias;
  TemperatureScale temperature_scale;
  BiasInstability bias_instability;
  WhiteNoise white_noise;
  BiasRandomWalk bias_random_walk;
  VibrationRectification vibration_rectification;
  Quantization quantization;

  // M = I + diag(k) + N of seed Eq. 1-2.
  Eigen::Matrix3d scaleMisalignmentMatrix() const;
  bool usesTemperature() const {
    return temperature_bias.isActive() || temperature_scale.isActive();
  }
  // Deterministic error y - x for the mean input x (excluding g-sensitivity). temperature_degC
  // may be NaN only when no temperature term is active (else std::invalid_argument).
  Eigen::Vector3d deterministicError(const Eigen::Vector3d& x, double temperature_degC,
                                     double vibration_regressor) const;
  bool hasStochastic() const {
    return bias_instability.isActive() || white_noise.isActive() || bias_random_walk.isActive();
  }
};

// One line of describe(): an active term, for reports.
struct ErrorTermDescription {
  std::string name;         // effect name as in diagnosis.json, e.g. "g_sensitivity"
  std::string sensor;       // "gyro" | "accel" | "both"
  std::string parameters;   // SI values, e.g. "k=[1.0e-03, 0, 0]"
  std::string explanation;  // one line of physics
};

struct ImuErrorModel {
  SensorErrorTerms gyro;
  SensorErrorTerms accel;
  GSensitivity g_sensitivity;                  // gyro only
  TimeOffset time_offset;                      // both
  LeverArm lever_arm;                          // accel (needs the angular rate)
  MountingMisalignment mounting_misalignment;  // both

  // Throws std::invalid_argument naming the offending key and value (e.g.
  // "ImuErrorModel: gyro.bias_instability.tau_s = -1 must be > 0").
  void validate() const;
  // True when no term is active (the output equals the input exactly).
  bool isIdeal() const;
  bool hasGeometry() const {
    return time_offset.isActive() || lever_arm.isActive() || mounting_misalignment.isActive();
  }

  // Deterministic sensor output (step 5 above) for mean inputs of the tested IMU (after geometry):
  // for fitting in calibration and mismatch finding. The error forms return y - x.
  Eigen::Vector3d gyroDeterministic(const Eigen::Vector3d& omega_true_rad_s,
                                    const Eigen::Vector3d& f_true_m_s2,
                                    double temperature_degC = std::nan(""),
                                    double vibration_regressor = 0.0) const;
  Eigen::Vector3d accelDeterministic(const Eigen::Vector3d& f_true_m_s2,
                                     double temperature_degC = std::nan(""),
                                     double vibration_regressor = 0.0) const;
  Eigen::Vector3d gyroDeterministicError(const Eigen::Vector3d& omega_true_rad_s,
                                         const Eigen::Vector3d& f_true_m_s2,
                                         double temperature_degC = std::nan(""),
                                         double vibration_regressor = 0.0) const;
  Eigen::Vector3d accelDeterministicError(const Eigen::Vector3d& f_true_m_s2,
                                          double temperature_degC = std::nan(""),
                                          double vibration_regressor = 0.0) const;

  // The active terms, in the order they are applied, with their parameters and physics.
  std::vector<ErrorTermDescription> describe() const;
};

// The stochastic part of a profile: white noise (ARW, VRW) and bias instability (sigma, tau).
ImuErrorModel stochasticErrorModel(const ImuProfile& profile);
// stochasticErrorModel plus one draw of the turn-on errors: constant bias ~ N(0, initial std,
// or the bias instability when the initial std is 0) and scale factor ~ N(0, scale std), per
// axis, from StandardNormalSampler(deriveStreamSeed(seed, 7)).
ImuErrorModel sampleErrorModel(const ImuProfile& profile, uint64_t seed);

// Steps A1-A3: lever arm, mounting misalignment, time offset. Throws std::invalid_argument when
// lever_arm or time_offset is active and the samples are not contiguous
// (|t_{k-1} - (t_k - dt_k)| > 1e-3 dt_k) or dt_s <= 0, naming the sample.
ImuSeries applyGeometry(const ImuSeries& reference, const ImuErrorModel& model);

// Steps B4-B8, sample by sample, with its own random state; no heap allocation per sample.
class ImuErrorGenerator {
 public:
  // Validates the model. The first apply() call starts the processes (stationary
  // Gauss-Markov draw); later calls propagate them over the sample's dt_s.
  ImuErrorGenerator(const ImuErrorModel& model, uint64_t seed);

  // Sensor errors for one sample whose increments already carry the geometry. Throws
  // std::invalid_argument if dt_s <= 0 or a temperature term is active and the sample has no
  // temperature.
  ImuSample apply(const ImuSample& tested_true);

  // A new record begins (a separate lab file: the sensor is set in a pose and settles before it
  // is logged). The vibration_rectification regressors restart from the record's first sample,
  // so the jump of the input between two records' poses is not taken for vibration; the noise
  // processes and the quantization remainder carry on (one sensor, one noise stream).
  void startRecord();

  const ImuErrorModel& model() const { return model_; }
  // Current stochastic bias states (for tests and truth output).
  Eigen::Vector3d gyroStochasticBias() const { return gyro_gm_.state() + gyro_rw_; }
  Eigen::Vector3d accelStochasticBias() const { return accel_gm_.state() + accel_rw_; }

 private:
  ImuErrorModel model_;
  StandardNormalSampler gyro_white_rng_, accel_white_rng_, gyro_gm_rng_, accel_gm_rng_,
      gyro_rw_rng_, accel_rw_rng_;
  GaussMarkov gyro_gm_, accel_gm_;
  Eigen::Vector3d gyro_rw_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_rw_ = Eigen::Vector3d::Zero();
  VibrationRegressor gyro_vib_, accel_vib_;
  Eigen::Vector3d gyro_quant_residual_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_quant_residual_ = Eigen::Vector3d::Zero();
  bool started_ = false;
};

// The whole chain: applyGeometry then ImuErrorGenerator over every sample.
ImuSeries applyErrors(const ImuSeries& ideal, const ImuErrorModel& model, uint64_t seed);

// The same chain over separate records of one sensor (lab sessions, in order): geometry per
// record, one ImuErrorGenerator whose noise streams run on from record to record (as
// applyErrors over the concatenation), startRecord() at the start of each.
std::vector<ImuSeries> applyErrorsToRecords(const std::vector<ImuSeries>& ideal_records,
                                            const ImuErrorModel& model, uint64_t seed);

}  // namespace graftnav
