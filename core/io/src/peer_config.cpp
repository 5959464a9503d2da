#include "graftnav/io/peer_config.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "graftnav/io/yaml_fields.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;
namespace yf = yaml_fields;
using namespace units;

constexpr double kMilliGalToMPerSec2 = 1e-5;  // 1 mGal = 1e-5 m/s^2
constexpr double kHourToSec = 3600.0;

// A per-axis value (scalar or [x, y, z]) reduced to graftnav's one value per sensor triad: the RMS
// over the axes, with a note when the axes differ.
double perAxis(const yf::Context& ctx, const YAML::Node& n, const std::string& key, PeerSetup* s) {
  if (n.IsScalar()) return yf::asDouble(ctx, n, key);
  const Eigen::Vector3d v = yf::asVector3(ctx, n, key);
  const double rms = std::sqrt(v.squaredNorm() / 3.0);
  if (v.maxCoeff() - v.minCoeff() > 1e-12 * std::max(1.0, v.cwiseAbs().maxCoeff())) {
    s->notes.push_back(
        fmt::format("{}: per-axis values [{}, {}, {}] replaced by their RMS {:.6g} "
                    "(graftnav models one value per triad)",
                    key, v.x(), v.y(), v.z(), rms));
  }
  return rms;
}

double nonNegative(const yf::Context& ctx, const YAML::Node& n, const std::string& key, double v) {
  if (v < 0.0) yf::fail(ctx, n, key, "must be >= 0, got " + yf::describe(n));
  return v;
}

// Data paths of the peers are relative to where the peer ran; try the yaml's folder, then cwd.
std::string resolveDataPath(const yf::Context& ctx, const YAML::Node& n, const std::string& key) {
  const std::string given = yf::asString(ctx, n, key);
  if (given.empty()) yf::fail(ctx, n, key, "empty path");
  std::vector<fs::path> tried;
  if (fs::path(given).is_absolute()) {
    tried.push_back(given);
  } else {
    tried.push_back(fs::absolute(fs::path(ctx.path).parent_path() / given));
    tried.push_back(fs::absolute(given));
  }
  for (const auto& p : tried)
    if (fs::is_regular_file(p)) return p.lexically_normal().string();
  std::string list;
  for (const auto& p : tried)
    list += (list.empty() ? "'" : ", '") + p.lexically_normal().string() + "'";
  yf::fail(ctx, n, key, "file '" + given + "' not found; tried " + list);
}

void readNoise(const yf::Context& ctx, const YAML::Node& sec, const std::string& prefix,
               PeerSetup* s) {
  ImuProfile& p = s->profile;
  auto need = [&](const char* key) { return yf::child(ctx, sec, prefix, key, true); };
  auto val = [&](const char* key) {
    const YAML::Node n = need(key);
    return nonNegative(ctx, n, yf::join(prefix, key), perAxis(ctx, n, yf::join(prefix, key), s));
  };
  p.arw_rad_sqrt_s = val("arw") * kDegPerSqrtHourToRadPerSqrtSec;
  p.vrw_m_s_sqrt_s = val("vrw") * kMPerSecPerSqrtHourToMPerSecPerSqrtSec;
  p.gyro_bias_instability_rad_s = val("gbstd") * kDegPerHourToRadPerSec;
  p.accel_bias_instability_m_s2 = val("abstd") * kMilliGalToMPerSec2;
  const double corr_s =
      yf::asDouble(ctx, need("corrtime"), yf::join(prefix, "corrtime")) * kHourToSec;
  if (!(corr_s > 0.0)) yf::fail(ctx, need("corrtime"), yf::join(prefix, "corrtime"), "must be > 0");
  p.gyro_bias_corr_time_s = p.accel_bias_corr_time_s = p.scale_corr_time_s = corr_s;
  if (yf::present(sec["gsstd"])) p.gyro_scale_std = val("gsstd") * kPpmToFraction;
  if (yf::present(sec["asstd"])) p.accel_scale_std = val("asstd") * kPpmToFraction;
  p.gyro_bias_initial_std_rad_s = p.gyro_bias_instability_rad_s;
  p.accel_bias_initial_std_m_s2 = p.accel_bias_instability_m_s2;
  // The grade only labels reports; chosen from the gyro bias instability.
  const double gb_deg_h = p.gyro_bias_instability_rad_s / kDegPerHourToRadPerSec;
  p.grade = gb_deg_h < 0.1   ? ImuGrade::kNavigation
            : gb_deg_h < 5.0 ? ImuGrade::kTactical
                             : ImuGrade::kMems;
  s->notes.push_back(
      fmt::format("grade '{}' assumed from the gyro bias instability {:.4g} deg/h "
                  "(labels only)",
                  imuGradeName(p.grade), gb_deg_h));
}

// A constant initial bias or scale estimate has no counterpart (graftnav starts them at zero).
void noteInitialErrors(const yf::Context& ctx, const YAML::Node& root, PeerSetup* s,
                       std::initializer_list<const char*> keys) {
  for (const char* key : keys) {
    const YAML::Node n = root[key];
    if (!yf::present(n)) continue;
    const Eigen::Vector3d v = yf::asVector3(ctx, n, key);
    if (v.cwiseAbs().maxCoeff() > 0.0) {
      s->notes.push_back(
          fmt::format("NOT CONVERTED: {} [{}, {}, {}]: graftnav starts the IMU errors "
                      "at zero; correct the IMU file or expect a different start",
                      key, v.x(), v.y(), v.z()));
    }
  }
}

void readCommon(const yf::Context& ctx, const YAML::Node& root, const char* imu_key,
                const char* gnss_key, PeerSetup* s) {
  s->imu_path = resolveDataPath(ctx, yf::child(ctx, root, "", imu_key, true), imu_key);
  s->gnss_path = resolveDataPath(ctx, yf::child(ctx, root, "", gnss_key, true), gnss_key);
  if (yf::present(root["imudatalen"])) {
    s->imu_columns = yf::asInt(ctx, root["imudatalen"], "imudatalen");
    if (s->imu_columns < 7) yf::fail(ctx, root["imudatalen"], "imudatalen", "must be >= 7");
  }
  s->imu_rate_hz = yf::requireDouble(ctx, root, "", "imudatarate");
  if (!(s->imu_rate_hz > 0.0)) yf::fail(ctx, root["imudatarate"], "imudatarate", "must be > 0");
  s->start_s = yf::requireDouble(ctx, root, "", "starttime");
  if (const auto end = yf::optionalDouble(ctx, root, "", "endtime"); end && *end > s->start_s)
    s->end_s = *end;
  if (yf::present(root["initvel"]))
    s->initial_velocity_ned_m_s = yf::asVector3(ctx, root["initvel"], "initvel");
  s->initial_euler_rad =
      yf::asVector3(ctx, yf::child(ctx, root, "", "initatt", true), "initatt") * kDegToRad;
  if (yf::present(root["antlever"])) {
    s->lever_arm_m = yf::asVector3(ctx, root["antlever"], "antlever");
  } else {
    s->notes.push_back("no antlever: the case has no lever_arm_m (a zero lever arm will be used)");
  }
  if (yf::present(root["outputpath"])) {
    s->notes.push_back("outputpath ignored: graftnav writes where `navigate --out` says");
  }
}

void readKfGins(const yf::Context& ctx, const YAML::Node& root, PeerSetup* s) {
  readCommon(ctx, root, "imupath", "gnsspath", s);
  const Eigen::Vector3d llh =
      yf::asVector3(ctx, yf::child(ctx, root, "", "initpos", true), "initpos");
  s->initial_position = Geodetic{llh.x() * kDegToRad, llh.y() * kDegToRad, llh.z()};
  if (yf::present(root["initposstd"]))
    s->initial_pos_std_m = yf::asVector3(ctx, root["initposstd"], "initposstd");
  if (yf::present(root["initvelstd"]))
    s->initial_vel_std_m_s = yf::asVector3(ctx, root["initvelstd"], "initvelstd");
  if (yf::present(root["initattstd"]))
    s->initial_att_std_rad = yf::asVector3(ctx, root["initattstd"], "initattstd") * kDegToRad;
  readNoise(ctx, yf::requireMap(ctx, root, "imunoise", yf::child(ctx, root, "", "imunoise", true)),
            "imunoise", s);
  if (yf::present(root["initbgstd"]))
    s->profile.gyro_bias_initial_std_rad_s =
        perAxis(ctx, root["initbgstd"], "initbgstd", s) * kDegPerHourToRadPerSec;
  if (yf::present(root["initbastd"]))
    s->profile.accel_bias_initial_std_m_s2 =
        perAxis(ctx, root["initbastd"], "initbastd", s) * kMilliGalToMPerSec2;
  for (const char* key : {"initsgstd", "initsastd"})
    if (yf::present(root[key]))
      s->notes.push_back(
          std::string("NOT CONVERTED: ") + key +
          ": graftnav's initial scale-factor sigma is the scale-factor std (gsstd/asstd)");
  noteInitialErrors(ctx, root, s, {"initgyrbias", "initaccbias", "initgyrscale", "initaccscale"});
  yf::warnUnknownKeys(
      ctx, root, "",
      {"imupath",      "gnsspath",     "outputpath", "imudatalen", "imudatarate", "starttime",
       "endtime",      "initpos",      "initvel",    "initatt",    "initgyrbias", "initaccbias",
       "initgyrscale", "initaccscale", "initposstd", "initvelstd", "initattstd",  "initbgstd",
       "initbastd",    "initsgstd",    "initsastd",  "imunoise",   "antlever"});
  yf::warnUnknownKeys(ctx, root["imunoise"], "imunoise",
                      {"arw", "vrw", "gbstd", "abstd", "gsstd", "asstd", "corrtime"});
}

// The odometer keys; the speed columns of the IMU file (imudatalen 8 or 9).
void readObGinsOdometer(const yf::Context& ctx, const YAML::Node& root, PeerSetup* s) {
  s->odometer_columns = std::min(std::max(s->imu_columns - 7, 0), 2);
  const YAML::Node odo = root["odometer"];
  if (!yf::present(odo) && !yf::present(root["odolever"]) && !yf::present(root["bodyangle"]))
    return;
  PeerOdometer o;
  if (yf::present(odo)) {
    if (!odo.IsMap()) yf::fail(ctx, odo, "odometer", "expected a map {isuseodo, std, srw}");
    if (yf::present(odo["isuseodo"]))
      o.enabled = yf::asBool(ctx, odo["isuseodo"], "odometer.isuseodo");
    if (yf::present(odo["std"])) {
      const Eigen::Vector3d density = yf::asVector3(ctx, odo["std"], "odometer.std");
      if (!(density.minCoeff() > 0.0))
        yf::fail(ctx, odo["std"], "odometer.std", "must be > 0 m/s on every axis");
      o.std_m_s = density * std::sqrt(o.rate_hz);
    }
    if (yf::present(odo["srw"])) {
      const double ppm = yf::asDouble(ctx, odo["srw"], "odometer.srw");
      nonNegative(ctx, odo["srw"], "odometer.srw", ppm);
      o.scale_random_walk_per_sqrt_s = ppm * kPpmToFraction;
    }
    yf::warnUnknownKeys(ctx, odo, "odometer", {"isuseodo", "std", "srw"});
  }
  if (yf::present(root["odolever"]))
    o.lever_arm_m = yf::asVector3(ctx, root["odolever"], "odolever");
  if (yf::present(root["bodyangle"]))
    o.mounting_rad = yf::asVector3(ctx, root["bodyangle"], "bodyangle") * kDegToRad;
  if (o.enabled && s->odometer_columns == 0) {
    yf::fail(ctx, root["imudatalen"] ? root["imudatalen"] : odo, "odometer.isuseodo",
             "the odometer is on but imudatalen is 7: its IMU file has no odometer column");
  }
  s->odometer = o;
  const Eigen::Vector3d density = o.std_m_s / std::sqrt(o.rate_hz);
  s->notes.push_back(fmt::format(
      "odometer: isuseodo {} -> odometer.enabled; std [{:g}, {:g}, {:g}] m/s/sqrt(Hz) -> "
      "odometer.std_m_s [{:.4g}, {:.4g}, {:.4g}] m/s at rate_hz {:g} (OB_GINS's std is a noise "
      "density: its preintegration grows the odometer displacement's variance by std^2 dt; one "
      "update's 1-sigma is std * sqrt(rate_hz); forward, lateral, vertical: OB_GINS's odometer "
      "also says the wheels do not slide; graftnav applies it as a vehicle-frame velocity "
      "update, OB_GINS inside its preintegration); odolever -> odometer.lever_arm_m; bodyangle "
      "[{}, {}, {}] deg -> odometer.mounting_deg (OB_GINS itself uses only pitch and yaw)",
      o.enabled, density.x(), density.y(), density.z(), o.std_m_s.x(), o.std_m_s.y(), o.std_m_s.z(),
      o.rate_hz, o.mounting_rad.x() / kDegToRad, o.mounting_rad.y() / kDegToRad,
      o.mounting_rad.z() / kDegToRad));
  if (o.scale_random_walk_per_sqrt_s) {
    s->notes.push_back(fmt::format(
        "odometer.srw {:g} ppm -> odometer.scale_random_walk_ppm_sqrt_s {:g} (OB_GINS's "
        "preintegration grows its odometer scale's variance by (srw 1e-6)^2 dt: a random walk "
        "of srw ppm/sqrt(s)); OB_GINS's config states no initial scale sigma (its code holds "
        "the scale of the newest node to a fixed 2 % prior): graftnav's default "
        "odometer.scale_std_ppm is used",
        *o.scale_random_walk_per_sqrt_s / kPpmToFraction,
        *o.scale_random_walk_per_sqrt_s / kPpmToFraction));
  }
}

void readObGinsOptions(const yf::Context& ctx, const YAML::Node& root, PeerSetup* s) {
  if (yf::present(root["windows"])) {
    s->window_nodes = yf::asInt(ctx, root["windows"], "windows");
    s->notes.push_back(
        fmt::format("windows {} taken as fgo.window_nodes (nodes about 1 s apart); "
                    "run navigate --estimator fgo-window for OB_GINS's optimizer",
                    *s->window_nodes));
  }
  if (yf::present(root["isearth"])) s->earth_rotation = yf::asBool(ctx, root["isearth"], "isearth");
  for (const char* key : {"num_iterations", "is_outlier_culling"}) {
    if (yf::present(root[key])) {
      s->notes.push_back(std::string(key) +
                         " not converted: graftnav's factor-graph solver keeps its own settings "
                         "(fgo: window_iterations, culling_rounds, robust_loss)");
    }
  }
  if (yf::present(root["gnssthreshold"])) {
    s->gnss_max_std_m = yf::asDouble(ctx, root["gnssthreshold"], "gnssthreshold");
    s->notes.push_back("gnssthreshold taken as gnss.max_horizontal_std_m and max_vertical_std_m");
  }
  readObGinsOdometer(ctx, root, s);
  if (yf::present(root["isuseoutage"]) && yf::asBool(ctx, root["isuseoutage"], "isuseoutage")) {
    PeerOutageSchedule o;
    o.first_start_s = yf::requireDouble(ctx, root, "", "outagetime");
    o.length_s = yf::requireDouble(ctx, root, "", "outagelen");
    o.period_s = yf::requireDouble(ctx, root, "", "outageperiod");
    if (!(o.length_s > 0.0) || !(o.period_s >= o.length_s))
      yf::fail(ctx, root["outagelen"], "outagelen", "needs 0 < outagelen <= outageperiod");
    if (o.first_start_s < s->start_s) {
      o.first_start_s += s->start_s;
      s->notes.push_back("outagetime below starttime: ASSUMED to count from starttime");
    } else {
      s->notes.push_back("outagetime ASSUMED to be a GNSS second of week");
    }
    s->outage_schedule = o;
  }
}

void readObGins(const yf::Context& ctx, const YAML::Node& root, PeerSetup* s) {
  readCommon(ctx, root, "imufile", "gnssfile", s);
  s->notes.push_back(
      "OB_GINS gives no initial position: taken from the first GNSS fix at or after "
      "starttime, moved from the antenna to the IMU with antlever and initatt");
  readNoise(ctx, yf::requireMap(ctx, root, "imumodel", yf::child(ctx, root, "", "imumodel", true)),
            "imumodel", s);
  s->notes.push_back("OB_GINS models no scale factors: scale-factor std 0");
  readObGinsOptions(ctx, root, s);
  noteInitialErrors(ctx, root, s, {"initgb", "initab"});
  yf::warnUnknownKeys(
      ctx, root, "",
      {"imufile",    "gnssfile",     "outputpath",    "windows",        "starttime",
       "endtime",    "initvel",      "initatt",       "initgb",         "initab",
       "imudatalen", "imudatarate",  "isearth",       "antlever",       "odolever",
       "bodyangle",  "odometer",     "imumodel",      "isuseoutage",    "outagetime",
       "outagelen",  "outageperiod", "gnssthreshold", "num_iterations", "is_outlier_culling"});
  yf::warnUnknownKeys(ctx, root["imumodel"], "imumodel",
                      {"arw", "vrw", "gbstd", "abstd", "corrtime"});
}

}  // namespace

PeerFormat peerFormatFromName(const std::string& name) {
  if (name == "kf-gins") return PeerFormat::kKfGins;
  if (name == "ob-gins") return PeerFormat::kObGins;
  throw std::invalid_argument("unknown peer format '" + name + "' (expected kf-gins or ob-gins)");
}

std::string peerFormatName(PeerFormat format) {
  return format == PeerFormat::kKfGins ? "kf-gins" : "ob-gins";
}

PeerSetup loadPeerConfig(PeerFormat format, const std::string& path,
                         std::vector<std::string>* warnings) {
  const yf::Context ctx{path, warnings};
  const YAML::Node root = yf::loadFile(path);
  if (!root.IsMap())
    throw std::runtime_error(path + ": expected a YAML map of " + peerFormatName(format) + " keys");
  PeerSetup s;
  s.format = format;
  s.config_path = path;
  if (format == PeerFormat::kKfGins) {
    readKfGins(ctx, root, &s);
  } else {
    readObGins(ctx, root, &s);
  }
  s.profile.name = peerFormatName(format) + " imunoise";
  if (!s.end_s) s.notes.push_back("endtime absent or -1: to the end of the IMU file");
  if (s.odometer_columns > 0) {
    s.notes.push_back(fmt::format(
        "imudatalen {}: the IMU file's column{} {} (odometer speed, m/s) moved to "
        "field/odometer.txt{}; the IMU copied with its first 7 columns",
        s.imu_columns, s.odometer_columns > 1 ? "s" : "", s.odometer_columns > 1 ? "8-9" : "8",
        s.odometer_columns > 1 ? " (the mean of the two wheels)" : ""));
  } else if (s.imu_columns > 7) {
    s.notes.push_back(fmt::format(
        "imudatalen {}: only the first 7 columns (time, increments) are used", s.imu_columns));
  }
  return s;
}

}  // namespace graftnav
