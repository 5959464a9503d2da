#include "graftnav/sim/sim_config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

#include "graftnav/io/imu_profile_io.h"
#include "graftnav/io/yaml_fields.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/nav/units.h"
#include "graftnav/io/file_errors.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;
namespace yf = yaml_fields;

// The simulation config's view of the YAML field helper (graftnav/io/yaml_fields.h): defaults
// for absent keys, errors naming the file, line and dotted key.
class Reader {
 public:
  Reader(std::string path, std::vector<std::string>* warnings) : ctx_{std::move(path), warnings} {}

  [[noreturn]] void fail(const YAML::Node& n, const std::string& key,
                         const std::string& msg) const {
    yf::fail(ctx_, n, key, msg);
  }

  template <typename Known = std::initializer_list<const char*>>
  void checkKeys(const YAML::Node& map, const std::string& prefix, const Known& known) const {
    if (!map.IsMap()) fail(map, prefix.empty() ? "(top level)" : prefix, "expected a map");
    yf::warnUnknownKeys(ctx_, map, prefix, known);
  }

  double num(const YAML::Node& map, const std::string& key, const std::string& full,
             double def) const {
    const YAML::Node n = map[key];
    return n ? yf::asDouble(ctx_, n, full) : def;
  }
  double requiredNum(const YAML::Node& map, const std::string& key, const std::string& full) const {
    if (!map[key]) fail(map, full, "required key missing");
    return num(map, key, full, 0.0);
  }
  std::string str(const YAML::Node& map, const std::string& key, const std::string& full,
                  const std::string& def) const {
    const YAML::Node n = map[key];
    return n ? yf::asString(ctx_, n, full) : def;
  }
  bool boolean(const YAML::Node& map, const std::string& key, const std::string& full,
               bool def) const {
    const YAML::Node n = map[key];
    return n ? yf::asBool(ctx_, n, full) : def;
  }
  // An absent key gives an empty list; `size` > 0 requires exactly that many numbers.
  std::vector<double> list(const YAML::Node& map, const std::string& key, const std::string& full,
                           int size) const {
    const YAML::Node n = map[key];
    return n ? yf::asDoubleList(ctx_, n, full, size > 0 ? size : -1) : std::vector<double>{};
  }
  std::optional<Eigen::Vector3d> vec3(const YAML::Node& map, const std::string& key,
                                      const std::string& full) const {
    const YAML::Node n = map[key];
    if (!n) return std::nullopt;
    return yf::asVector3(ctx_, n, full);
  }
  std::string resolve(const std::string& p) const {
    if (p.empty() || fs::path(p).is_absolute()) return p;
    return (fs::path(ctx_.path).parent_path() / p).lexically_normal().string();
  }
  const std::string& path() const { return ctx_.path; }

 private:
  yf::Context ctx_;
};

Eigen::Matrix3d offDiagonal(const std::vector<double>& v, double scale) {
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  if (v.empty()) return N;
  N(0, 1) = v[0] * scale;
  N(0, 2) = v[1] * scale;
  N(1, 0) = v[2] * scale;
  N(1, 2) = v[3] * scale;
  N(2, 0) = v[4] * scale;
  N(2, 1) = v[5] * scale;
  return N;
}

// The tested IMU's extra sensor errors: biases, scale factors, non-orthogonality, temperature
// and g-sensitivity (config units, converted to SI).
void parseExtraLinearTerms(const Reader& r, const YAML::Node& n, const std::string& key,
                           ImuErrorModel* e) {
  if (auto v = r.vec3(n, "gyro_bias_deg_h", key + ".gyro_bias_deg_h")) {
    e->gyro.constant_bias.b = *v * units::kDegPerHourToRadPerSec;
  }
  if (auto v = r.vec3(n, "accel_bias_mg", key + ".accel_bias_mg")) {
    e->accel.constant_bias.b = *v * units::kMilliGToMPerSec2;
  }
  if (auto v = r.vec3(n, "gyro_scale_ppm", key + ".gyro_scale_ppm")) {
    e->gyro.scale_factor.k = *v * units::kPpmToFraction;
  }
  if (auto v = r.vec3(n, "accel_scale_ppm", key + ".accel_scale_ppm")) {
    e->accel.scale_factor.k = *v * units::kPpmToFraction;
  }
  e->gyro.non_orthogonality.N = offDiagonal(
      r.list(n, "gyro_nonorthogonality_urad", key + ".gyro_nonorthogonality_urad", 6), 1e-6);
  e->accel.non_orthogonality.N = offDiagonal(
      r.list(n, "accel_nonorthogonality_urad", key + ".accel_nonorthogonality_urad", 6), 1e-6);
  if (auto v = r.vec3(n, "gyro_bias_per_degC_deg_h", key + ".gyro_bias_per_degC_deg_h")) {
    e->gyro.temperature_bias.per_degC = *v * units::kDegPerHourToRadPerSec;
  }
  if (auto v = r.vec3(n, "accel_bias_per_degC_mg", key + ".accel_bias_per_degC_mg")) {
    e->accel.temperature_bias.per_degC = *v * units::kMilliGToMPerSec2;
  }
  const double t_ref = r.num(n, "temperature_ref_degC", key + ".temperature_ref_degC", 25.0);
  e->gyro.temperature_bias.t_ref_degC = t_ref;
  e->accel.temperature_bias.t_ref_degC = t_ref;
  const auto g = r.list(n, "g_sensitivity_deg_h_per_g", key + ".g_sensitivity_deg_h_per_g", 9);
  if (!g.empty()) {
    for (int i = 0; i < 9; ++i) {
      e->g_sensitivity.G(i / 3, i % 3) =
          g[i] * units::kDegPerHourToRadPerSec / units::kStandardGravity_m_s2;
    }
  }
}

// The field-mounting geometry and the non-linear sensor terms of the tested IMU.
void parseExtraGeometryAndNonlinearTerms(const Reader& r, const YAML::Node& n,
                                         const std::string& key, ImuErrorModel* e) {
  // Geometry of the field mounting (tested relative to the reference IMU; never in the lab).
  e->time_offset.tau_s = r.num(n, "time_offset_s", key + ".time_offset_s", 0.0);
  if (auto v = r.vec3(n, "lever_arm_m", key + ".lever_arm_m")) e->lever_arm.r_m = *v;
  if (auto v = r.vec3(n, "mounting_misalignment_deg", key + ".mounting_misalignment_deg")) {
    e->mounting_misalignment.rotation_rad = *v * units::kDegToRad;
  }
  // Non-linear sensor terms (also in the lab files: they belong to the sensor).
  const auto ppm3 = [&](const char* k, Eigen::Vector3d* dst) {
    if (auto v = r.vec3(n, k, key + "." + k)) *dst = *v * units::kPpmToFraction;
  };
  ppm3("gyro_scale_asymmetry_pos_ppm", &e->gyro.scale_asymmetry.k_pos);
  ppm3("gyro_scale_asymmetry_neg_ppm", &e->gyro.scale_asymmetry.k_neg);
  ppm3("accel_scale_asymmetry_pos_ppm", &e->accel.scale_asymmetry.k_pos);
  ppm3("accel_scale_asymmetry_neg_ppm", &e->accel.scale_asymmetry.k_neg);
  if (auto v = r.vec3(n, "gyro_scale_nonlinearity_per_rad_s",
                      key + ".gyro_scale_nonlinearity_per_rad_s")) {
    e->gyro.scale_nonlinearity.k2 = *v;
  }
  if (auto v = r.vec3(n, "accel_scale_nonlinearity_per_m_s2",
                      key + ".accel_scale_nonlinearity_per_m_s2")) {
    e->accel.scale_nonlinearity.k2 = *v;
  }
}

// Vibration rectification and quantization of the tested IMU.
void parseExtraRectificationAndQuantization(const Reader& r, const YAML::Node& n,
                                            const std::string& key, ImuErrorModel* e) {
  for (const char* sensor : {"gyro", "accel"}) {
    const std::string vk = std::string(sensor) + "_vibration_rectification";
    const YAML::Node vn = n[vk];
    if (!vn) continue;
    r.checkKeys(vn, key + "." + vk, {"coeff", "regressor", "window_s"});
    VibrationRectification& vr = sensor == std::string("gyro") ? e->gyro.vibration_rectification
                                                               : e->accel.vibration_rectification;
    const auto coeff = r.vec3(vn, "coeff", key + "." + vk + ".coeff");
    if (!coeff) r.fail(vn, key + "." + vk + ".coeff", "required key missing");
    vr.coeff = *coeff;  // SI: unit of the sensor per unit of the regressor
    vr.regressor = r.str(vn, "regressor", key + "." + vk + ".regressor", vr.regressor);
    if (vr.regressor != "specific_force_hp_sq" && vr.regressor != "angular_rate_hp_sq") {
      r.fail(vn["regressor"], key + "." + vk + ".regressor",
             "'" + vr.regressor + "' is not specific_force_hp_sq or angular_rate_hp_sq");
    }
    vr.window_s = r.num(vn, "window_s", key + "." + vk + ".window_s", vr.window_s);
    if (!(vr.window_s > 0.0)) r.fail(vn["window_s"], key + "." + vk + ".window_s", "must be > 0");
  }
  if (auto v = r.vec3(n, "gyro_quantization_rad", key + ".gyro_quantization_rad")) {
    e->gyro.quantization.step = *v;
  }
  if (auto v = r.vec3(n, "accel_quantization_m_s", key + ".accel_quantization_m_s")) {
    e->accel.quantization.step = *v;
  }
}

SimImuConfig parseImu(const Reader& r, const YAML::Node& n, const std::string& key, bool tested,
                      std::vector<std::string>* warnings) {
  if (!n) r.fail(n, key, "required section missing");
  std::set<std::string> known = {"profile", "turn_on_errors", "bias_instability_scale"};
  if (tested) {
    known.insert({"gyro_bias_deg_h",
                  "accel_bias_mg",
                  "gyro_scale_ppm",
                  "accel_scale_ppm",
                  "gyro_nonorthogonality_urad",
                  "accel_nonorthogonality_urad",
                  "g_sensitivity_deg_h_per_g",
                  "gyro_bias_per_degC_deg_h",
                  "accel_bias_per_degC_mg",
                  "temperature_ref_degC",
                  "time_offset_s",
                  "lever_arm_m",
                  "mounting_misalignment_deg",
                  "gyro_scale_asymmetry_pos_ppm",
                  "gyro_scale_asymmetry_neg_ppm",
                  "accel_scale_asymmetry_pos_ppm",
                  "accel_scale_asymmetry_neg_ppm",
                  "gyro_scale_nonlinearity_per_rad_s",
                  "accel_scale_nonlinearity_per_m_s2",
                  "gyro_vibration_rectification",
                  "accel_vibration_rectification",
                  "gyro_quantization_rad",
                  "accel_quantization_m_s"});
  }
  r.checkKeys(n, key, known);
  SimImuConfig c;
  if (!n["profile"]) r.fail(n, key + ".profile", "required key missing");
  c.profile_path = r.resolve(r.str(n, "profile", key + ".profile", ""));
  try {
    c.profile = loadImuProfile(c.profile_path, warnings);
  } catch (const std::exception& e) {
    r.fail(n["profile"], key + ".profile", e.what());
  }
  c.turn_on_errors = r.boolean(n, "turn_on_errors", key + ".turn_on_errors", true);
  c.bias_instability_scale =
      r.num(n, "bias_instability_scale", key + ".bias_instability_scale", 1.0);
  if (!(c.bias_instability_scale >= 0.0)) {
    r.fail(n["bias_instability_scale"], key + ".bias_instability_scale", "must be >= 0");
  }
  if (tested) {
    parseExtraLinearTerms(r, n, key, &c.extra);
    parseExtraGeometryAndNonlinearTerms(r, n, key, &c.extra);
    parseExtraRectificationAndQuantization(r, n, key, &c.extra);
  }
  return c;
}

MotionScript parseScript(const Reader& r, const YAML::Node& n) {
  const std::string k = "trajectory.script";
  r.checkKeys(n, k,
              {"start_time_s", "start_position", "initial_yaw_deg", "ramp_s", "roll_deg_per_g",
               "segments"});
  MotionScript s;
  s.start_time_s = r.requiredNum(n, "start_time_s", k + ".start_time_s");
  const auto p = r.vec3(n, "start_position", k + ".start_position");
  if (!p) r.fail(n, k + ".start_position", "required key missing");
  s.start = {(*p)[0] * units::kDegToRad, (*p)[1] * units::kDegToRad, (*p)[2]};
  s.initial_yaw_rad = r.num(n, "initial_yaw_deg", k + ".initial_yaw_deg", 0.0) * units::kDegToRad;
  s.ramp_s = r.num(n, "ramp_s", k + ".ramp_s", 1.0);
  s.roll_per_lateral_g_rad =
      r.num(n, "roll_deg_per_g", k + ".roll_deg_per_g", 4.0) * units::kDegToRad;
  const YAML::Node segs = n["segments"];
  if (!segs || !segs.IsSequence()) r.fail(n, k + ".segments", "required list missing");
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const YAML::Node g = segs[i];
    const std::string gk = k + ".segments[" + std::to_string(i) + "]";
    r.checkKeys(g, gk, {"type", "duration_s", "to_speed_m_s", "rate_deg_s", "radius_m", "laps"});
    MotionSegment m;
    try {
      m.type = motionSegmentType(r.str(g, "type", gk + ".type", ""));
    } catch (const std::exception& e) {
      r.fail(g, gk + ".type", e.what());
    }
    m.duration_s = r.num(g, "duration_s", gk + ".duration_s", 0.0);
    m.to_speed_m_s = r.num(g, "to_speed_m_s", gk + ".to_speed_m_s", 0.0);
    m.rate_rad_s = r.num(g, "rate_deg_s", gk + ".rate_deg_s", 0.0) * units::kDegToRad;
    m.radius_m = r.num(g, "radius_m", gk + ".radius_m", 0.0);
    m.laps = static_cast<int>(r.num(g, "laps", gk + ".laps", 1.0));
    s.segments.push_back(m);
  }
  try {
    s.validate();
  } catch (const std::exception& e) {
    r.fail(segs, k, e.what());
  }
  return s;
}

RoadVibrationOptions parseVibration(const Reader& r, const YAML::Node& v) {
  const std::string k = "trajectory.vibration";
  r.checkKeys(v, k,
              {"accel_rms_m_s2", "gyro_rms_deg_s", "band_hz", "components", "seed",
               "half_amplitude_speed_m_s"});
  RoadVibrationOptions o;
  auto nonNegative = [&](const char* key, double def) {
    const double x = r.num(v, key, k + "." + key, def);
    if (x < 0.0) r.fail(v[key], k + "." + key, "must be >= 0");
    return x;
  };
  o.accel_rms_m_s2 = nonNegative("accel_rms_m_s2", 0.0);
  o.gyro_rms_rad_s = nonNegative("gyro_rms_deg_s", 0.0) * units::kDegToRad;
  if (v["band_hz"]) {
    const auto b = r.list(v, "band_hz", k + ".band_hz", 2);
    if (!(b[0] > 0.0 && b[1] >= b[0])) {
      r.fail(v["band_hz"], k + ".band_hz", "expected [low, high] with 0 < low <= high");
    }
    o.band_low_hz = b[0];
    o.band_high_hz = b[1];
  }
  const double n = r.num(v, "components", k + ".components", o.components);
  if (!(n >= 3.0) || n != std::floor(n)) {
    r.fail(v["components"], k + ".components", "must be an integer >= 3 (one per axis)");
  }
  o.components = static_cast<int>(n);
  const double seed = r.num(v, "seed", k + ".seed", static_cast<double>(o.seed));
  if (seed < 0.0 || seed != std::floor(seed))
    r.fail(v["seed"], k + ".seed", "must be an integer >= 0");
  o.seed = static_cast<uint64_t>(seed);
  o.half_amplitude_speed_m_s = r.num(v, "half_amplitude_speed_m_s", k + ".half_amplitude_speed_m_s",
                                     o.half_amplitude_speed_m_s);
  if (!(o.half_amplitude_speed_m_s > 0.0)) {
    r.fail(v["half_amplitude_speed_m_s"], k + ".half_amplitude_speed_m_s", "must be > 0");
  }
  return o;
}

// Relative error of an n-node Gauss-Legendre rule on the increment of a sinusoid of frequency f
// over one IMU interval h (integral of cos(a x) on [-1, 1], a = pi f h; exact 2 sin(a) / a).
double quadratureRelativeError(int nodes, double f_hz, double h_s) {
  const GaussLegendreRule rule = gaussLegendreRule(nodes);
  const double a = units::kPi * f_hz * h_s;
  double q = 0.0;
  for (std::size_t i = 0; i < rule.nodes.size(); ++i)
    q += rule.weights[i] * std::cos(a * rule.nodes[i]);
  const double exact = a > 0.0 ? 2.0 * std::sin(a) / a : 2.0;
  return std::abs(q / exact - 1.0);
}

}  // namespace

void SimConfig::validate() const {
  if (name.empty()) throw std::invalid_argument("SimConfig: name is empty");
  if (!(imu_rate_hz > 0.0)) {
    throw std::invalid_argument("SimConfig: imu_rate_hz must be > 0, got " +
                                std::to_string(imu_rate_hz));
  }
  if (!(truth_rate_hz > 0.0) ||
      std::abs(imu_rate_hz / truth_rate_hz - std::round(imu_rate_hz / truth_rate_hz)) > 1e-9) {
    throw std::invalid_argument("SimConfig: truth_rate_hz = " + std::to_string(truth_rate_hz) +
                                " must divide imu_rate_hz = " + std::to_string(imu_rate_hz));
  }
  if (track.has_value() == script.has_value()) {
    throw std::invalid_argument(
        "SimConfig: give exactly one of trajectory.track and "
        "trajectory.script");
  }
  if (track) {
    track->smoothing.validate();
    if (track->start_offset_s < 0.0 || track->duration_s < 0.0 || track->margin_s < 0.0) {
      throw std::invalid_argument(
          "SimConfig: trajectory start_offset_s, duration_s, margin_s "
          "must be >= 0");
    }
    const RoadVibrationOptions& vib = track->smoothing.vibration;
    if (vib.enabled()) {
      // The IMU samples the vibration: keep it below Nyquist, and let the Gauss-Legendre rule of
      // the ideal IMU integrate its increments to 1e-4 (4 nodes at 100 Hz: 4e-7 at 35 Hz).
      if (!(vib.band_high_hz < 0.5 * imu_rate_hz)) {
        throw std::invalid_argument("SimConfig: trajectory.vibration.band_hz upper edge " +
                                    std::to_string(vib.band_high_hz) +
                                    " Hz must be below the "
                                    "Nyquist frequency imu_rate_hz / 2 = " +
                                    std::to_string(0.5 * imu_rate_hz) + " Hz");
      }
      if (quadrature_nodes < 1 || quadrature_nodes > 64 ||
          quadratureRelativeError(quadrature_nodes, vib.band_high_hz, 1.0 / imu_rate_hz) > 1e-4) {
        throw std::invalid_argument(
            "SimConfig: quadrature_nodes = " + std::to_string(quadrature_nodes) +
            " integrates trajectory.vibration at " + std::to_string(vib.band_high_hz) +
            " Hz with a relative error above 1e-4 at imu_rate_hz = " + std::to_string(imu_rate_hz) +
            "; use more nodes");
      }
    }
  }
  if (script) script->validate();
  if (tested_imu.extra.gyro.usesTemperature() || tested_imu.extra.accel.usesTemperature()) {
    if (!temperature) {
      throw std::invalid_argument(
          "SimConfig: tested_imu has temperature coefficients but the "
          "config has no temperature section");
    }
  }
  gnss.validate();
  lab.validate();
  reference_imu.extra.validate();
  tested_imu.extra.validate();
}

SimTrackSource parseTrackSource(const Reader& r, const YAML::Node& trj) {
  SimTrackSource t;
  t.path = r.resolve(r.str(trj, "track", "trajectory.track", ""));
  t.start_offset_s = r.num(trj, "start_offset_s", "trajectory.start_offset_s", 0.0);
  t.duration_s = r.num(trj, "duration_s", "trajectory.duration_s", 0.0);
  t.margin_s = r.num(trj, "margin_s", "trajectory.margin_s", 5.0);
  t.smoothing.position_cutoff_hz = r.num(trj, "position_cutoff_hz", "trajectory.position_cutoff_hz",
                                         t.smoothing.position_cutoff_hz);
  t.smoothing.attitude_cutoff_hz = r.num(trj, "attitude_cutoff_hz", "trajectory.attitude_cutoff_hz",
                                         t.smoothing.attitude_cutoff_hz);
  t.smoothing.roll_per_lateral_g_rad =
      r.num(trj, "roll_deg_per_g", "trajectory.roll_deg_per_g", 4.0) * units::kDegToRad;
  const double osc = r.num(trj, "oscillation_scale", "trajectory.oscillation_scale", 1.0);
  for (auto& o : t.smoothing.oscillations) o.amplitude_rad *= osc;
  if (const YAML::Node v = trj["vibration"]) {
    t.smoothing.vibration = parseVibration(r, v);
  }
  return t;
}

// The GNSS and temperature sections.
void parseGnssAndTemperature(const Reader& r, const YAML::Node& root, SimConfig& c) {
  if (const YAML::Node g = root["gnss"]) {
    r.checkKeys(g, "gnss", {"rate_hz", "noise_std_neu_m", "lever_arm_m"});
    c.gnss.rate_hz = r.num(g, "rate_hz", "gnss.rate_hz", c.gnss.rate_hz);
    if (auto v = r.vec3(g, "noise_std_neu_m", "gnss.noise_std_neu_m")) c.gnss.noise_std_neu_m = *v;
    if (auto v = r.vec3(g, "lever_arm_m", "gnss.lever_arm_m")) c.gnss.lever_arm_b_m = *v;
  }
  if (const YAML::Node t = root["temperature"]) {
    r.checkKeys(t, "temperature", {"start_degC", "end_degC", "time_constant_s", "lab_degC"});
    SimTemperature st;
    st.start_degC = r.requiredNum(t, "start_degC", "temperature.start_degC");
    st.end_degC = r.num(t, "end_degC", "temperature.end_degC", st.start_degC);
    st.time_constant_s = r.num(t, "time_constant_s", "temperature.time_constant_s", 900.0);
    if (!(st.time_constant_s > 0.0)) {
      r.fail(t["time_constant_s"], "temperature.time_constant_s", "must be > 0");
    }
    if (t["lab_degC"]) st.lab_degC = r.requiredNum(t, "lab_degC", "temperature.lab_degC");
    c.temperature = st;
  }
}

// The odometer section (config units: ppm, deg).
OdometerSimOptions parseOdometer(const Reader& r, const YAML::Node& o) {
  r.checkKeys(o, "odometer",
              {"rate_hz", "scale_error_ppm", "noise_std_m_s", "quantization_m_s", "lever_arm_m",
               "mounting_deg"});
  OdometerSimOptions opt;
  opt.rate_hz = r.num(o, "rate_hz", "odometer.rate_hz", opt.rate_hz);
  opt.scale_error = r.num(o, "scale_error_ppm", "odometer.scale_error_ppm", 0.0) * 1e-6;
  opt.noise_std_m_s = r.num(o, "noise_std_m_s", "odometer.noise_std_m_s", opt.noise_std_m_s);
  opt.quantization_m_s =
      r.num(o, "quantization_m_s", "odometer.quantization_m_s", opt.quantization_m_s);
  if (auto v = r.vec3(o, "lever_arm_m", "odometer.lever_arm_m")) opt.lever_arm_b_m = *v;
  if (auto v = r.vec3(o, "mounting_deg", "odometer.mounting_deg"))
    opt.mounting_rad = *v * units::kDegToRad;
  try {
    opt.validate();
  } catch (const std::invalid_argument& e) {
    r.fail(o, "odometer", e.what());
  }
  return opt;
}

// The lab section: where and how long the lab records are (config units, converted to SI).
void parseLab(const Reader& r, const YAML::Node& l, SimConfig& c) {
  r.checkKeys(l, "lab",
              {"latitude_deg", "longitude_deg", "height_m", "start_time_s", "static_duration_s",
               "static_attitude_deg", "six_position_duration_s", "rate_table_deg_s",
               "rate_table_turns", "tilt_duration_s", "tilts", "common_random_numbers"});
  c.lab_common_random_numbers =
      r.boolean(l, "common_random_numbers", "lab.common_random_numbers", false);
  c.lab.latitude_rad = r.num(l, "latitude_deg", "lab.latitude_deg", 30.53) * units::kDegToRad;
  c.lab.longitude_rad = r.num(l, "longitude_deg", "lab.longitude_deg", 114.35) * units::kDegToRad;
  c.lab.height_m = r.num(l, "height_m", "lab.height_m", c.lab.height_m);
  c.lab.start_time_s = r.num(l, "start_time_s", "lab.start_time_s", c.lab.start_time_s);
  c.lab.static_duration_s =
      r.num(l, "static_duration_s", "lab.static_duration_s", c.lab.static_duration_s);
  if (auto v = r.vec3(l, "static_attitude_deg", "lab.static_attitude_deg")) {
    c.lab.static_euler_rad = *v * units::kDegToRad;
  }
  c.lab.six_position_duration_s = r.num(l, "six_position_duration_s", "lab.six_position_duration_s",
                                        c.lab.six_position_duration_s);
  if (l["rate_table_deg_s"]) {
    c.lab.rate_table_rad_s.clear();
    for (double v : r.list(l, "rate_table_deg_s", "lab.rate_table_deg_s", 0)) {
      c.lab.rate_table_rad_s.push_back(v * units::kDegToRad);
    }
  }
  c.lab.rate_table_turns =
      static_cast<int>(r.num(l, "rate_table_turns", "lab.rate_table_turns", 1.0));
  c.lab.tilt_duration_s = r.num(l, "tilt_duration_s", "lab.tilt_duration_s", c.lab.tilt_duration_s);
  if (const YAML::Node t = l["tilts"]) {
    if (!t.IsMap()) r.fail(t, "lab.tilts", "expected a map name: [roll, pitch, yaw]");
    for (const auto& kv : t) {
      const std::string name = kv.first.as<std::string>();
      const auto v = r.vec3(t, name, "lab.tilts." + name);
      c.lab.tilt_euler_rad[name] = *v * units::kDegToRad;
    }
  }
}

SimConfig loadSimConfig(const std::string& path, std::vector<std::string>* warnings) {
  if (!fs::exists(path)) throw MissingFileError(path, path + ": sim config file not found");
  const YAML::Node root = yf::loadFile(path);
  const Reader r(path, warnings);
  r.checkKeys(
      root, "",
      {"name", "seed", "gnss_week", "imu_rate_hz", "quadrature_nodes", "truth_rate_hz",
       "trajectory", "reference_imu", "tested_imu", "gnss", "lab", "temperature", "odometer"});
  SimConfig c;
  c.source_path = path;
  c.name = r.str(root, "name", "name", c.name);
  c.seed = static_cast<uint64_t>(r.num(root, "seed", "seed", 1.0));
  c.gnss_week = static_cast<int>(r.num(root, "gnss_week", "gnss_week", c.gnss_week));
  c.imu_rate_hz = r.num(root, "imu_rate_hz", "imu_rate_hz", c.imu_rate_hz);
  c.quadrature_nodes =
      static_cast<int>(r.num(root, "quadrature_nodes", "quadrature_nodes", c.quadrature_nodes));
  c.truth_rate_hz = r.num(root, "truth_rate_hz", "truth_rate_hz", c.imu_rate_hz);

  const YAML::Node trj = root["trajectory"];
  if (!trj) r.fail(root, "trajectory", "required section missing");
  r.checkKeys(trj, "trajectory",
              {"track", "start_offset_s", "duration_s", "margin_s", "position_cutoff_hz",
               "attitude_cutoff_hz", "roll_deg_per_g", "oscillation_scale", "vibration", "script"});
  if (trj["track"]) c.track = parseTrackSource(r, trj);
  if (trj["script"]) c.script = parseScript(r, trj["script"]);

  c.reference_imu = parseImu(r, root["reference_imu"], "reference_imu", false, warnings);
  c.tested_imu = parseImu(r, root["tested_imu"], "tested_imu", true, warnings);

  parseGnssAndTemperature(r, root, c);
  if (const YAML::Node o = root["odometer"]) c.odometer = parseOdometer(r, o);
  c.lab.rate_hz = c.imu_rate_hz;
  c.lab.quadrature_nodes = c.quadrature_nodes;
  if (const YAML::Node l = root["lab"]) parseLab(r, l, c);
  try {
    c.validate();
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  return c;
}

SimTemperature SimTemperature::lab() const {
  if (!lab_degC) return *this;
  SimTemperature c = *this;
  c.start_degC = c.end_degC = *lab_degC;
  return c;
}

double SimTemperature::at(double dt_s) const {
  return end_degC + (start_degC - end_degC) * std::exp(-dt_s / time_constant_s);
}

ImuErrorModel buildSimErrorModel(const SimImuConfig& imu, uint64_t seed, bool ideal) {
  if (ideal) return ImuErrorModel{};
  ImuErrorModel m =
      imu.turn_on_errors ? sampleErrorModel(imu.profile, seed) : stochasticErrorModel(imu.profile);
  // The profile's bias instability stays in case.yaml (the navigator's model); only the simulated
  // sensor's Gauss-Markov wander is scaled (0: a sensor with only the terms grafting models).
  m.gyro.bias_instability.sigma *= imu.bias_instability_scale;
  m.accel.bias_instability.sigma *= imu.bias_instability_scale;
  const ImuErrorModel& x = imu.extra;
  m.gyro.constant_bias.b += x.gyro.constant_bias.b;
  m.accel.constant_bias.b += x.accel.constant_bias.b;
  m.gyro.scale_factor.k += x.gyro.scale_factor.k;
  m.accel.scale_factor.k += x.accel.scale_factor.k;
  m.gyro.non_orthogonality.N += x.gyro.non_orthogonality.N;
  m.accel.non_orthogonality.N += x.accel.non_orthogonality.N;
  m.g_sensitivity.G += x.g_sensitivity.G;
  m.gyro.temperature_bias = x.gyro.temperature_bias;
  m.accel.temperature_bias = x.accel.temperature_bias;
  m.gyro.scale_asymmetry = x.gyro.scale_asymmetry;
  m.accel.scale_asymmetry = x.accel.scale_asymmetry;
  m.gyro.scale_nonlinearity = x.gyro.scale_nonlinearity;
  m.accel.scale_nonlinearity = x.accel.scale_nonlinearity;
  m.gyro.vibration_rectification = x.gyro.vibration_rectification;
  m.accel.vibration_rectification = x.accel.vibration_rectification;
  m.gyro.quantization = x.gyro.quantization;
  m.accel.quantization = x.accel.quantization;
  m.time_offset = x.time_offset;
  m.lever_arm = x.lever_arm;
  m.mounting_misalignment = x.mounting_misalignment;
  m.validate();
  return m;
}

ImuErrorModel labErrorModel(const ImuErrorModel& field_model) {
  ImuErrorModel m = field_model;
  m.time_offset = TimeOffset{};
  m.lever_arm = LeverArm{};
  m.mounting_misalignment = MountingMisalignment{};
  return m;
}

}  // namespace graftnav
