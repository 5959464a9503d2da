#include "graftnav/imu/imu_error_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graftnav/nav/rotation.h"

namespace graftnav {

namespace {

// Random stream ids (documented in imu_error_model.h).
constexpr uint64_t kStreamGyroWhite = 1;
constexpr uint64_t kStreamAccelWhite = 2;
constexpr uint64_t kStreamGyroGm = 3;
constexpr uint64_t kStreamAccelGm = 4;
constexpr uint64_t kStreamGyroRw = 5;
constexpr uint64_t kStreamAccelRw = 6;
constexpr uint64_t kStreamTurnOn = 7;

std::string fmtVec(const Eigen::Vector3d& v) {
  return fmt::format("[{:.6g}, {:.6g}, {:.6g}]", v.x(), v.y(), v.z());
}

std::string fmtMat(const Eigen::Matrix3d& m) {
  return fmt::format("[{}, {}, {}]", fmtVec(m.row(0).transpose()), fmtVec(m.row(1).transpose()),
                     fmtVec(m.row(2).transpose()));
}

void requireFinite(const Eigen::MatrixXd& v, const std::string& key) {
  if (!v.allFinite()) {
    throw std::invalid_argument("ImuErrorModel: " + key + " must be finite");
  }
}

void requireNonNegative(const Eigen::Vector3d& v, const std::string& key) {
  requireFinite(v, key);
  for (int i = 0; i < 3; ++i) {
    if (v[i] < 0.0) {
      throw std::invalid_argument(
          fmt::format("ImuErrorModel: {}[{}] = {} must be >= 0", key, i, v[i]));
    }
  }
}

void validateSensor(const SensorErrorTerms& s, const std::string& p) {
  requireFinite(s.constant_bias.b, p + ".constant_bias.b");
  requireFinite(s.scale_factor.k, p + ".scale_factor.k");
  requireFinite(s.non_orthogonality.N, p + ".non_orthogonality.N");
  for (int i = 0; i < 3; ++i) {
    if (s.non_orthogonality.N(i, i) != 0.0) {
      throw std::invalid_argument(fmt::format(
          "ImuErrorModel: {}.non_orthogonality.N({},{}) = {} must be 0 (the diagonal is "
          "scale_factor.k)",
          p, i, i, s.non_orthogonality.N(i, i)));
    }
  }
  requireFinite(s.scale_asymmetry.k_pos, p + ".scale_asymmetry.k_pos");
  requireFinite(s.scale_asymmetry.k_neg, p + ".scale_asymmetry.k_neg");
  requireFinite(s.scale_nonlinearity.k2, p + ".scale_nonlinearity.k2");
  requireFinite(s.temperature_bias.per_degC, p + ".temperature_bias.per_degC");
  if (!std::isfinite(s.temperature_bias.t_ref_degC)) {
    throw std::invalid_argument("ImuErrorModel: " + p +
                                ".temperature_bias.t_ref_degC must be finite");
  }
  requireFinite(s.temperature_scale.per_degC, p + ".temperature_scale.per_degC");
  requireNonNegative(s.bias_instability.sigma, p + ".bias_instability.sigma");
  if (!(s.bias_instability.tau_s > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "ImuErrorModel: {}.bias_instability.tau_s = {} must be > 0", p, s.bias_instability.tau_s));
  }
  requireNonNegative(s.white_noise.density, p + ".white_noise.density");
  requireNonNegative(s.bias_random_walk.density, p + ".bias_random_walk.density");
  const auto& v = s.vibration_rectification;
  requireFinite(v.coeff, p + ".vibration_rectification.coeff");
  if (!(v.window_s > 0.0) || !std::isfinite(v.window_s)) {
    throw std::invalid_argument(fmt::format(
        "ImuErrorModel: {}.vibration_rectification.window_s = {} must be finite and > 0", p,
        v.window_s));
  }
  if (v.isActive() && !VibrationRegressor::isKnownName(v.regressor)) {
    throw std::invalid_argument(
        fmt::format("ImuErrorModel: {}.vibration_rectification.regressor = '{}' is unknown (use "
                    "specific_force_hp_sq or angular_rate_hp_sq)",
                    p, v.regressor));
  }
  requireNonNegative(s.quantization.step, p + ".quantization.step");
}

bool sensorActive(const SensorErrorTerms& s) {
  return s.constant_bias.isActive() || s.scale_factor.isActive() ||
         s.non_orthogonality.isActive() || s.scale_asymmetry.isActive() ||
         s.scale_nonlinearity.isActive() || s.temperature_bias.isActive() ||
         s.temperature_scale.isActive() || s.bias_instability.isActive() ||
         s.white_noise.isActive() || s.bias_random_walk.isActive() ||
         s.vibration_rectification.isActive() || s.quantization.isActive();
}

bool sensorDeterministicActive(const SensorErrorTerms& s) {
  return s.constant_bias.isActive() || s.scale_factor.isActive() ||
         s.non_orthogonality.isActive() || s.scale_asymmetry.isActive() ||
         s.scale_nonlinearity.isActive() || s.usesTemperature() ||
         s.vibration_rectification.isActive();
}

void describeSensor(const SensorErrorTerms& s, const std::string& sensor, bool gyro,
                    const GSensitivity* g, std::vector<ErrorTermDescription>& out) {
  const char* unit = gyro ? "rad/s" : "m/s^2";
  if (s.constant_bias.isActive()) {
    out.push_back({"constant_bias", sensor, fmt::format("b={} {}", fmtVec(s.constant_bias.b), unit),
                   "fixed offset of the sensor zero (turn-on bias)"});
  }
  if (s.scale_factor.isActive()) {
    out.push_back({"scale_factor", sensor, "k=" + fmtVec(s.scale_factor.k),
                   "gain error of each axis, output = (1 + k) x (seed Eq. 1-2, S)"});
  }
  if (s.non_orthogonality.isActive()) {
    out.push_back({"non_orthogonality", sensor, "N=" + fmtMat(s.non_orthogonality.N) + " rad",
                   "sensing axes not mutually perpendicular: each axis picks up the others "
                   "(seed Eq. 1-2, N)"});
  }
  if (s.scale_asymmetry.isActive()) {
    out.push_back(
        {"scale_asymmetry", sensor,
         "k_pos=" + fmtVec(s.scale_asymmetry.k_pos) + " k_neg=" + fmtVec(s.scale_asymmetry.k_neg),
         "different gain for positive and negative inputs"});
  }
  if (s.scale_nonlinearity.isActive()) {
    out.push_back({"scale_nonlinearity", sensor,
                   fmt::format("k2={} 1/({})", fmtVec(s.scale_nonlinearity.k2), unit),
                   "quadratic departure from a straight input-output line, y = x + k2 x^2"});
  }
  if (s.temperature_bias.isActive()) {
    out.push_back(
        {"temperature_bias", sensor,
         fmt::format("per_degC={} {}/degC t_ref_degC={:.6g}", fmtVec(s.temperature_bias.per_degC),
                     unit, s.temperature_bias.t_ref_degC),
         "bias drifting linearly with sensor temperature"});
  }
  if (s.temperature_scale.isActive()) {
    out.push_back({"temperature_scale", sensor,
                   fmt::format("per_degC={} 1/degC t_ref_degC={:.6g}",
                               fmtVec(s.temperature_scale.per_degC), s.temperature_bias.t_ref_degC),
                   "gain drifting linearly with sensor temperature"});
  }
  if (g != nullptr && g->isActive()) {
    out.push_back({"g_sensitivity", sensor, "G=" + fmtMat(g->G) + " rad/s per m/s^2",
                   "gyro bias proportional to specific force (proof-mass unbalance)"});
  }
  if (s.vibration_rectification.isActive()) {
    const auto& v = s.vibration_rectification;
    out.push_back({"vibration_rectification", sensor,
                   fmt::format("coeff={} regressor={} window_s={:.6g}", fmtVec(v.coeff),
                               v.regressor, v.window_s),
                   "vibration rectified into a bias by non-linear or asymmetric sensor response"});
  }
  if (s.bias_instability.isActive()) {
    out.push_back({"bias_instability", sensor,
                   fmt::format("sigma={} {} tau_s={:.6g}", fmtVec(s.bias_instability.sigma), unit,
                               s.bias_instability.tau_s),
                   "slowly wandering bias, first-order Gauss-Markov (flicker floor of the Allan "
                   "deviation)"});
  }
  if (s.bias_random_walk.isActive()) {
    out.push_back({"bias_random_walk", sensor,
                   fmt::format("density={} {}/sqrt(s)", fmtVec(s.bias_random_walk.density), unit),
                   gyro ? "rate random walk: gyro bias diffusing without bound"
                        : "acceleration random walk: accelerometer bias diffusing without bound"});
  }
  if (s.white_noise.isActive()) {
    out.push_back({"white_noise", sensor,
                   fmt::format("density={} {}", fmtVec(s.white_noise.density),
                               gyro ? "rad/sqrt(s)" : "m/s/sqrt(s)"),
                   gyro ? "angle random walk: wide-band gyro noise, increment std ARW sqrt(dt)"
                        : "velocity random walk: wide-band accelerometer noise, increment std VRW "
                          "sqrt(dt)"});
  }
  if (s.quantization.isActive()) {
    out.push_back({"quantization", sensor,
                   fmt::format("step={} {}", fmtVec(s.quantization.step), gyro ? "rad" : "m/s"),
                   "increments output as whole counts, remainder carried to the next sample"});
  }
}

}  // namespace

// ---- SensorErrorTerms ------------------------------------------------------------------------

Eigen::Matrix3d SensorErrorTerms::scaleMisalignmentMatrix() const {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  M.diagonal() += scale_factor.k;
  M += non_orthogonality.N;
  return M;
}

Eigen::Vector3d SensorErrorTerms::deterministicError(const Eigen::Vector3d& x,
                                                     double temperature_degC,
                                                     double vibration_regressor) const {
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  if (constant_bias.isActive()) e += constant_bias.b;
  if (scale_factor.isActive()) e += scale_factor.k.cwiseProduct(x);
  if (non_orthogonality.isActive()) e += non_orthogonality.N * x;
  if (scale_asymmetry.isActive()) {
    for (int i = 0; i < 3; ++i) {
      e[i] += (x[i] >= 0.0 ? scale_asymmetry.k_pos[i] : scale_asymmetry.k_neg[i]) * x[i];
    }
  }
  if (scale_nonlinearity.isActive()) {
    e += scale_nonlinearity.k2.cwiseProduct(x.cwiseProduct(x));
  }
  if (usesTemperature()) {
    if (std::isnan(temperature_degC)) {
      throw std::invalid_argument(
          "SensorErrorTerms::deterministicError: a temperature term is active but the "
          "temperature is NaN (no temperature column)");
    }
    const double dT = temperature_degC - temperature_bias.t_ref_degC;
    e += temperature_bias.per_degC * dT;
    e += dT * temperature_scale.per_degC.cwiseProduct(x);
  }
  if (vibration_rectification.isActive()) e += vibration_rectification.coeff * vibration_regressor;
  return e;
}

// ---- ImuErrorModel ---------------------------------------------------------------------------

void ImuErrorModel::validate() const {
  validateSensor(gyro, "gyro");
  validateSensor(accel, "accel");
  requireFinite(g_sensitivity.G, "g_sensitivity.G");
  if (!std::isfinite(time_offset.tau_s)) {
    throw std::invalid_argument("ImuErrorModel: time_offset.tau_s must be finite");
  }
  requireFinite(lever_arm.r_m, "lever_arm.r_m");
  requireFinite(mounting_misalignment.rotation_rad, "mounting_misalignment.rotation_rad");
}

bool ImuErrorModel::isIdeal() const {
  return !sensorActive(gyro) && !sensorActive(accel) && !g_sensitivity.isActive() && !hasGeometry();
}

Eigen::Vector3d ImuErrorModel::gyroDeterministicError(const Eigen::Vector3d& omega_true_rad_s,
                                                      const Eigen::Vector3d& f_true_m_s2,
                                                      double temperature_degC,
                                                      double vibration_regressor) const {
  Eigen::Vector3d e =
      gyro.deterministicError(omega_true_rad_s, temperature_degC, vibration_regressor);
  if (g_sensitivity.isActive()) e += g_sensitivity.G * f_true_m_s2;
  return e;
}

Eigen::Vector3d ImuErrorModel::accelDeterministicError(const Eigen::Vector3d& f_true_m_s2,
                                                       double temperature_degC,
                                                       double vibration_regressor) const {
  return accel.deterministicError(f_true_m_s2, temperature_degC, vibration_regressor);
}

Eigen::Vector3d ImuErrorModel::gyroDeterministic(const Eigen::Vector3d& omega_true_rad_s,
                                                 const Eigen::Vector3d& f_true_m_s2,
                                                 double temperature_degC,
                                                 double vibration_regressor) const {
  return omega_true_rad_s + gyroDeterministicError(omega_true_rad_s, f_true_m_s2, temperature_degC,
                                                   vibration_regressor);
}

Eigen::Vector3d ImuErrorModel::accelDeterministic(const Eigen::Vector3d& f_true_m_s2,
                                                  double temperature_degC,
                                                  double vibration_regressor) const {
  return f_true_m_s2 + accelDeterministicError(f_true_m_s2, temperature_degC, vibration_regressor);
}

std::vector<ErrorTermDescription> ImuErrorModel::describe() const {
  std::vector<ErrorTermDescription> out;
  if (lever_arm.isActive()) {
    out.push_back({"lever_arm", "accel", "r_m=" + fmtVec(lever_arm.r_m) + " m",
                   "tested IMU displaced from the reference IMU: extra specific force "
                   "omega_dot x r + omega x (omega x r) of the rotating body (size effect)"});
  }
  if (mounting_misalignment.isActive()) {
    out.push_back({"mounting_misalignment", "both",
                   "rotation_rad=" + fmtVec(mounting_misalignment.rotation_rad),
                   "tested IMU mounted rotated from the reference body frame, omega_t = C_tb "
                   "omega, f_t = C_tb f"});
  }
  if (time_offset.isActive()) {
    out.push_back({"time_offset", "both", fmt::format("tau_s={:.6g}", time_offset.tau_s),
                   "time tags late by tau_s: the sample tagged t was measured at t - tau_s"});
  }
  describeSensor(gyro, "gyro", true, &g_sensitivity, out);
  describeSensor(accel, "accel", false, nullptr, out);
  return out;
}

// ---- profiles ----------------------------------------------------------------------------

ImuErrorModel stochasticErrorModel(const ImuProfile& p) {
  ImuErrorModel m;
  m.gyro.white_noise.density.setConstant(p.arw_rad_sqrt_s);
  m.accel.white_noise.density.setConstant(p.vrw_m_s_sqrt_s);
  m.gyro.bias_instability.sigma.setConstant(p.gyro_bias_instability_rad_s);
  m.gyro.bias_instability.tau_s = p.gyro_bias_corr_time_s;
  m.accel.bias_instability.sigma.setConstant(p.accel_bias_instability_m_s2);
  m.accel.bias_instability.tau_s = p.accel_bias_corr_time_s;
  m.validate();
  return m;
}

ImuErrorModel sampleErrorModel(const ImuProfile& p, uint64_t seed) {
  ImuErrorModel m = stochasticErrorModel(p);
  StandardNormalSampler rng(deriveStreamSeed(seed, kStreamTurnOn));
  const double gb = p.gyro_bias_initial_std_rad_s > 0.0 ? p.gyro_bias_initial_std_rad_s
                                                        : p.gyro_bias_instability_rad_s;
  const double ab = p.accel_bias_initial_std_m_s2 > 0.0 ? p.accel_bias_initial_std_m_s2
                                                        : p.accel_bias_instability_m_s2;
  m.gyro.constant_bias.b = gb * rng.next3();
  m.accel.constant_bias.b = ab * rng.next3();
  m.gyro.scale_factor.k = p.gyro_scale_std * rng.next3();
  m.accel.scale_factor.k = p.accel_scale_std * rng.next3();
  return m;
}

// ---- sensor generator --------------------------------------------------------------------

namespace {
const ImuErrorModel& validated(const ImuErrorModel& m) {
  m.validate();
  return m;
}
}  // namespace

ImuErrorGenerator::ImuErrorGenerator(const ImuErrorModel& model, uint64_t seed)
    : model_(validated(model)),
      gyro_white_rng_(deriveStreamSeed(seed, kStreamGyroWhite)),
      accel_white_rng_(deriveStreamSeed(seed, kStreamAccelWhite)),
      gyro_gm_rng_(deriveStreamSeed(seed, kStreamGyroGm)),
      accel_gm_rng_(deriveStreamSeed(seed, kStreamAccelGm)),
      gyro_rw_rng_(deriveStreamSeed(seed, kStreamGyroRw)),
      accel_rw_rng_(deriveStreamSeed(seed, kStreamAccelRw)),
      gyro_gm_(model.gyro.bias_instability),
      accel_gm_(model.accel.bias_instability),
      gyro_vib_(model.gyro.vibration_rectification.window_s),
      accel_vib_(model.accel.vibration_rectification.window_s) {}

namespace {

// Steps B5-B8 for one triad; x is the mean input, inc the increment (updated in place).
void applySensor(const SensorErrorTerms& s, const Eigen::Vector3d& det_error, double dt,
                 bool started, GaussMarkov& gm, StandardNormalSampler& gm_rng, Eigen::Vector3d& rw,
                 StandardNormalSampler& rw_rng, StandardNormalSampler& white_rng,
                 Eigen::Vector3d& quant_residual, Eigen::Vector3d& inc) {
  Eigen::Vector3d rate_error = det_error;
  if (s.bias_instability.isActive()) {
    if (!started) {
      gm.initialize(gm_rng);
    } else {
      gm.propagate(dt, gm_rng);
    }
    rate_error += gm.state();
  }
  if (s.bias_random_walk.isActive()) {
    if (started) rw += std::sqrt(dt) * s.bias_random_walk.density.cwiseProduct(rw_rng.next3());
    rate_error += rw;
  }
  inc += rate_error * dt;
  if (s.white_noise.isActive()) {
    inc += std::sqrt(dt) * s.white_noise.density.cwiseProduct(white_rng.next3());
  }
  if (s.quantization.isActive()) {
    for (int i = 0; i < 3; ++i) {
      const double step = s.quantization.step[i];
      if (step <= 0.0) continue;
      const double v = inc[i] + quant_residual[i];
      const double q = step * std::round(v / step);
      quant_residual[i] = v - q;
      inc[i] = q;
    }
  }
}

}  // namespace

ImuSample ImuErrorGenerator::apply(const ImuSample& in) {
  const double dt = in.dt_s;
  if (!(dt > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "ImuErrorGenerator::apply: sample t={:.6f} has dt_s = {} (must be > 0)", in.t_s, dt));
  }
  if ((model_.gyro.usesTemperature() || model_.accel.usesTemperature()) && !in.hasTemperature()) {
    throw std::invalid_argument(fmt::format(
        "ImuErrorGenerator::apply: a temperature term is active but sample t={:.6f} has no "
        "temperature",
        in.t_s));
  }
  ImuSample out = in;
  const Eigen::Vector3d omega = in.dtheta_rad / dt;
  const Eigen::Vector3d f = in.dvel_m_s / dt;

  // B4 vibration regressors.
  double r_g = 0.0, r_a = 0.0;
  const auto& vg = model_.gyro.vibration_rectification;
  const auto& va = model_.accel.vibration_rectification;
  if (vg.isActive())
    r_g = gyro_vib_.update(VibrationRegressor::usesAngularRate(vg.regressor) ? omega : f, dt);
  if (va.isActive())
    r_a = accel_vib_.update(VibrationRegressor::usesAngularRate(va.regressor) ? omega : f, dt);

  // B5 deterministic errors.
  Eigen::Vector3d e_g = Eigen::Vector3d::Zero();
  if (sensorDeterministicActive(model_.gyro) || model_.g_sensitivity.isActive()) {
    e_g = model_.gyroDeterministicError(omega, f, in.temperature_degC, r_g);
  }
  Eigen::Vector3d e_a = Eigen::Vector3d::Zero();
  if (sensorDeterministicActive(model_.accel)) {
    e_a = model_.accelDeterministicError(f, in.temperature_degC, r_a);
  }

  // B6-B8.
  applySensor(model_.gyro, e_g, dt, started_, gyro_gm_, gyro_gm_rng_, gyro_rw_, gyro_rw_rng_,
              gyro_white_rng_, gyro_quant_residual_, out.dtheta_rad);
  applySensor(model_.accel, e_a, dt, started_, accel_gm_, accel_gm_rng_, accel_rw_, accel_rw_rng_,
              accel_white_rng_, accel_quant_residual_, out.dvel_m_s);
  started_ = true;
  return out;
}

void ImuErrorGenerator::startRecord() {
  gyro_vib_.reset();
  accel_vib_.reset();
}

ImuSeries applyErrors(const ImuSeries& ideal, const ImuErrorModel& model, uint64_t seed) {
  ImuSeries out = model.hasGeometry() ? applyGeometry(ideal, model) : ideal;
  ImuErrorGenerator gen(model, seed);
  for (ImuSample& s : out) s = gen.apply(s);
  return out;
}

std::vector<ImuSeries> applyErrorsToRecords(const std::vector<ImuSeries>& ideal_records,
                                            const ImuErrorModel& model, uint64_t seed) {
  ImuErrorGenerator gen(model, seed);
  std::vector<ImuSeries> out;
  out.reserve(ideal_records.size());
  for (const ImuSeries& rec : ideal_records) {
    out.push_back(model.hasGeometry() ? applyGeometry(rec, model) : rec);
    gen.startRecord();
    for (ImuSample& s : out.back()) s = gen.apply(s);
  }
  return out;
}

}  // namespace graftnav
