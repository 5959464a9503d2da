#include "graftnav/io/imu_profile_io.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"
#include "graftnav/io/yaml_fields.h"

namespace graftnav {

namespace yf = yaml_fields;

namespace {
constexpr const char* kNoiseKeys[] = {"arw_deg_rt_h", "vrw_m_s_rt_h", "gyro_bias_instability_deg_h",
                                      "accel_bias_instability_mg"};

double nonNegative(const yf::Context& ctx, const YAML::Node& map, const std::string& prefix,
                   const char* key) {
  const double v = yf::requireDouble(ctx, map, prefix, key);
  if (v < 0.0)
    yf::fail(ctx, map[key], yf::join(prefix, key), "must be >= 0, got " + yf::describe(map[key]));
  return v;
}

std::optional<double> optionalNonNegative(const yf::Context& ctx, const YAML::Node& map,
                                          const std::string& prefix, const char* key,
                                          bool strictly_positive = false) {
  const auto v = yf::optionalDouble(ctx, map, prefix, key);
  if (v && (*v < 0.0 || (strictly_positive && *v == 0.0)))
    yf::fail(ctx, map[key], yf::join(prefix, key),
             std::string(strictly_positive ? "must be > 0" : "must be >= 0") + ", got " +
                 yf::describe(map[key]));
  return v;
}
// The optional `plausible_ranges:` block (plausible_ranges.h): a sensor class (default: the
// grade's) and per-term overrides in unit-named keys. The only place their units are converted.
PlausibleRanges parsePlausibleRanges(const yf::Context& ctx, const YAML::Node& node,
                                     const std::string& prefix, ImuGrade grade) {
  const YAML::Node block = node["plausible_ranges"];
  const std::string key = yf::join(prefix, "plausible_ranges");
  std::string sensor_class = sensorClassForGrade(grade);
  if (!yf::present(block)) return plausibleRangesForClass(sensor_class);
  if (!block.IsMap()) yf::fail(ctx, block, key, "expected a map, got " + yf::describe(block));
  struct Override {
    const char* file_key;
    double PlausibleRanges::*field;
    double to_si;
  };
  const Override overrides[] = {
      {"gyro_scale_max_ppm", &PlausibleRanges::gyro_scale_max, units::kPpmToFraction},
      {"accel_scale_max_ppm", &PlausibleRanges::accel_scale_max, units::kPpmToFraction},
      {"gyro_nonorthogonality_max_deg", &PlausibleRanges::gyro_nonorthogonality_max_rad,
       units::kDegToRad},
      {"accel_nonorthogonality_max_deg", &PlausibleRanges::accel_nonorthogonality_max_rad,
       units::kDegToRad},
      {"gyro_scale_asymmetry_max_ppm", &PlausibleRanges::gyro_scale_asymmetry_max,
       units::kPpmToFraction},
      {"accel_scale_asymmetry_max_ppm", &PlausibleRanges::accel_scale_asymmetry_max,
       units::kPpmToFraction},
      {"gyro_scale_nonlinearity_max_per_rad_s",
       &PlausibleRanges::gyro_scale_nonlinearity_max_per_rad_s, 1.0},
      {"accel_scale_nonlinearity_max_per_m_s2",
       &PlausibleRanges::accel_scale_nonlinearity_max_per_m_s2, 1.0},
      {"g_sensitivity_max_deg_h_per_g", &PlausibleRanges::g_sensitivity_max_rad_s_per_m_s2,
       units::kDegPerHourToRadPerSec / units::kStandardGravity_m_s2}};
  yf::warnUnknownKeys(ctx, block, key,
                      {"sensor_class", "source", "gyro_scale_max_ppm", "accel_scale_max_ppm",
                       "gyro_nonorthogonality_max_deg", "accel_nonorthogonality_max_deg",
                       "gyro_scale_asymmetry_max_ppm", "accel_scale_asymmetry_max_ppm",
                       "gyro_scale_nonlinearity_max_per_rad_s",
                       "accel_scale_nonlinearity_max_per_m_s2", "g_sensitivity_max_deg_h_per_g"});
  if (yf::present(block["sensor_class"]))
    sensor_class = yf::asString(ctx, block["sensor_class"], yf::join(key, "sensor_class"));
  PlausibleRanges r;
  try {
    r = plausibleRangesForClass(sensor_class);
  } catch (const std::invalid_argument& e) {
    yf::fail(ctx, block["sensor_class"], yf::join(key, "sensor_class"), e.what());
  }
  if (yf::present(block["source"]))
    r.source = yf::asString(ctx, block["source"], yf::join(key, "source"));
  for (const Override& o : overrides)
    if (const auto v = optionalNonNegative(ctx, block, key, o.file_key, true))
      r.*(o.field) = *v * o.to_si;
  return r;
}
}  // namespace

ImuProfileParse parseImuProfileNode(const YAML::Node& node, const std::string& file_path,
                                    const std::string& prefix, bool require_noise,
                                    std::vector<std::string>* warnings) {
  const yf::Context ctx{file_path, warnings};
  if (!node.IsMap())
    yf::fail(ctx, node, prefix.empty() ? "(top level)" : prefix,
             "expected a map, got " + yf::describe(node));
  yf::warnUnknownKeys(
      ctx, node, prefix,
      {"name", "grade", "arw_deg_rt_h", "vrw_m_s_rt_h", "gyro_bias_instability_deg_h",
       "accel_bias_instability_mg", "gyro_scale_ppm", "accel_scale_ppm", "correlation_time_s",
       "gyro_bias_correlation_time_s", "accel_bias_correlation_time_s", "scale_correlation_time_s",
       "gyro_bias_initial_deg_h", "accel_bias_initial_mg", "gyro_bias_repeatability_deg_h",
       "accel_bias_repeatability_mg", "plausible_ranges"});
  ImuProfileParse out;
  ImuProfile& p = out.profile;
  if (yf::present(node["name"])) p.name = yf::asString(ctx, node["name"], yf::join(prefix, "name"));
  const std::string grade_text =
      yf::asString(ctx, yf::child(ctx, node, prefix, "grade", true), yf::join(prefix, "grade"));
  if (!parseImuGrade(grade_text, &p.grade))
    yf::fail(ctx, node["grade"], yf::join(prefix, "grade"),
             "expected navigation, tactical or mems, got " + yf::describe(node["grade"]));

  int noise_present = 0;
  for (const char* k : kNoiseKeys) noise_present += yf::present(node[k]) ? 1 : 0;
  out.noise_given = require_noise || noise_present > 0;
  if (out.noise_given) {
    // All four are required together (a partial noise specification is an error).
    p.arw_rad_sqrt_s =
        nonNegative(ctx, node, prefix, "arw_deg_rt_h") * units::kDegPerSqrtHourToRadPerSqrtSec;
    p.vrw_m_s_sqrt_s = nonNegative(ctx, node, prefix, "vrw_m_s_rt_h") *
                       units::kMPerSecPerSqrtHourToMPerSecPerSqrtSec;
    p.gyro_bias_instability_rad_s = nonNegative(ctx, node, prefix, "gyro_bias_instability_deg_h") *
                                    units::kDegPerHourToRadPerSec;
    p.accel_bias_instability_m_s2 =
        nonNegative(ctx, node, prefix, "accel_bias_instability_mg") * units::kMilliGToMPerSec2;
  }
  p.gyro_scale_std = optionalNonNegative(ctx, node, prefix, "gyro_scale_ppm").value_or(0.0) *
                     units::kPpmToFraction;
  p.accel_scale_std = optionalNonNegative(ctx, node, prefix, "accel_scale_ppm").value_or(0.0) *
                      units::kPpmToFraction;
  const double tau =
      optionalNonNegative(ctx, node, prefix, "correlation_time_s", true).value_or(3600.0);
  p.gyro_bias_corr_time_s =
      optionalNonNegative(ctx, node, prefix, "gyro_bias_correlation_time_s", true).value_or(tau);
  p.accel_bias_corr_time_s =
      optionalNonNegative(ctx, node, prefix, "accel_bias_correlation_time_s", true).value_or(tau);
  p.scale_corr_time_s =
      optionalNonNegative(ctx, node, prefix, "scale_correlation_time_s", true).value_or(tau);
  const auto g0 = optionalNonNegative(ctx, node, prefix, "gyro_bias_initial_deg_h");
  const auto a0 = optionalNonNegative(ctx, node, prefix, "accel_bias_initial_mg");
  p.gyro_bias_initial_std_rad_s =
      g0 ? *g0 * units::kDegPerHourToRadPerSec : p.gyro_bias_instability_rad_s;
  p.accel_bias_initial_std_m_s2 =
      a0 ? *a0 * units::kMilliGToMPerSec2 : p.accel_bias_instability_m_s2;
  const auto gr = optionalNonNegative(ctx, node, prefix, "gyro_bias_repeatability_deg_h");
  const auto ar = optionalNonNegative(ctx, node, prefix, "accel_bias_repeatability_mg");
  if (gr) p.gyro_bias_repeatability_rad_s = *gr * units::kDegPerHourToRadPerSec;
  if (ar) p.accel_bias_repeatability_m_s2 = *ar * units::kMilliGToMPerSec2;
  p.plausible_ranges = parsePlausibleRanges(ctx, node, prefix, p.grade);
  return out;
}

ImuProfile loadImuProfile(const std::string& path, std::vector<std::string>* warnings) {
  const YAML::Node root = yf::loadFile(path);
  ImuProfile p = parseImuProfileNode(root, path, "", true, warnings).profile;
  if (p.name.empty()) p.name = std::filesystem::path(path).stem().string();
  return p;
}

void emitImuProfile(YAML::Emitter& out, const ImuProfile& p, bool with_noise) {
  out << YAML::BeginMap;
  if (!p.name.empty()) out << YAML::Key << "name" << YAML::Value << p.name;
  out << YAML::Key << "grade" << YAML::Value << imuGradeName(p.grade);
  if (with_noise) {
    out << YAML::Key << "arw_deg_rt_h" << YAML::Value
        << p.arw_rad_sqrt_s / units::kDegPerSqrtHourToRadPerSqrtSec;
    out << YAML::Key << "vrw_m_s_rt_h" << YAML::Value
        << p.vrw_m_s_sqrt_s / units::kMPerSecPerSqrtHourToMPerSecPerSqrtSec;
    out << YAML::Key << "gyro_bias_instability_deg_h" << YAML::Value
        << p.gyro_bias_instability_rad_s / units::kDegPerHourToRadPerSec;
    out << YAML::Key << "accel_bias_instability_mg" << YAML::Value
        << p.accel_bias_instability_m_s2 / units::kMilliGToMPerSec2;
    out << YAML::Key << "gyro_bias_initial_deg_h" << YAML::Value
        << p.gyro_bias_initial_std_rad_s / units::kDegPerHourToRadPerSec;
    out << YAML::Key << "accel_bias_initial_mg" << YAML::Value
        << p.accel_bias_initial_std_m_s2 / units::kMilliGToMPerSec2;
    if (p.gyro_bias_repeatability_rad_s >= 0.0) {
      out << YAML::Key << "gyro_bias_repeatability_deg_h" << YAML::Value
          << p.gyro_bias_repeatability_rad_s / units::kDegPerHourToRadPerSec;
    }
    if (p.accel_bias_repeatability_m_s2 >= 0.0) {
      out << YAML::Key << "accel_bias_repeatability_mg" << YAML::Value
          << p.accel_bias_repeatability_m_s2 / units::kMilliGToMPerSec2;
    }
  }
  if (!with_noise) {  // a grade-only section ({grade: mems}): the other fields mean "unknown"
    out << YAML::EndMap;
    return;
  }
  out << YAML::Key << "gyro_scale_ppm" << YAML::Value << p.gyro_scale_std / units::kPpmToFraction;
  out << YAML::Key << "accel_scale_ppm" << YAML::Value << p.accel_scale_std / units::kPpmToFraction;
  out << YAML::Key << "gyro_bias_correlation_time_s" << YAML::Value << p.gyro_bias_corr_time_s;
  out << YAML::Key << "accel_bias_correlation_time_s" << YAML::Value << p.accel_bias_corr_time_s;
  out << YAML::Key << "scale_correlation_time_s" << YAML::Value << p.scale_corr_time_s;
  out << YAML::EndMap;
}

void saveImuProfile(const std::string& path, const ImuProfile& profile) {
  YAML::Emitter out;
  out.SetDoublePrecision(15);
  emitImuProfile(out, profile, true);
  if (!out.good()) throw std::runtime_error(path + ": YAML emitter error: " + out.GetLastError());
  writeFileAtomically(
      path, std::string("# IMU profile in the seed's Table 1 units (see imu_profile_io.h)\n") +
                out.c_str() + "\n");
}

}  // namespace graftnav
