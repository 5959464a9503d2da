#include "run_config.h"

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>

#include "graftnav/core/units.h"

namespace graftnav::app {
namespace {

std::string where(const std::string& path, const YAML::Node& n, const std::string& key) {
  return path + ":" + std::to_string(n.Mark().line + 1) + ": key '" + key + "'";
}

template <typename T>
void read(const YAML::Node& sec, const std::string& sec_name, const char* key, T* out,
          const std::string& path) {
  const YAML::Node n = sec[key];
  if (!n) return;
  try {
    *out = n.as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where(path, n, sec_name + "." + key) + ": wrong type ('" +
                             YAML::Dump(n) + "')");
  }
}

void warnUnknown(const YAML::Node& sec, const std::string& sec_name,
                 const std::set<std::string>& known, const std::string& path,
                 std::vector<std::string>* warnings) {
  if (!warnings || !sec.IsMap()) return;
  for (const auto& kv : sec) {
    const std::string k = kv.first.as<std::string>();
    if (!known.count(k)) {
      warnings->push_back(where(path, kv.first, sec_name.empty() ? k : sec_name + "." + k) +
                          " unknown, ignored");
    }
  }
}

}  // namespace

RunConfig loadRunConfig(const std::string& path, std::vector<std::string>* warnings) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(path + ": cannot open the run config");
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ":" + std::to_string(e.mark.line + 1) + ": YAML error: " + e.msg);
  }
  RunConfig c;
  if (!root || root.IsNull()) return c;
  if (!root.IsMap()) throw std::runtime_error(path + ": the run config must be a YAML map");
  warnUnknown(root, "", {"outages", "ekf", "evaluation"}, path, warnings);

  if (const YAML::Node o = root["outages"]) {
    c.outages_given = true;
    read(o, "outages", "length_s", &c.outages.length_s, path);
    read(o, "outages", "period_s", &c.outages.period_s, path);
    read(o, "outages", "start_s", &c.outages.start_s, path);
    read(o, "outages", "end_margin_s", &c.outages.end_margin_s, path);
    read(o, "outages", "enabled", &c.outages.enabled, path);
    if (const YAML::Node w = o["windows"]) {
      if (!w.IsSequence()) throw std::runtime_error(where(path, w, "outages.windows") + ": expected a list of [start, end]");
      for (const auto& p : w) {
        if (!p.IsSequence() || p.size() != 2) {
          throw std::runtime_error(where(path, p, "outages.windows") + ": each window is [start_s, end_s]");
        }
        TimeWindow tw{p[0].as<double>(), p[1].as<double>()};
        if (!(tw.end_s > tw.start_s)) {
          throw std::runtime_error(where(path, p, "outages.windows") + ": start must be < end");
        }
        c.outages.explicit_windows.push_back(tw);
      }
    }
    warnUnknown(o, "outages", {"length_s", "period_s", "start_s", "end_margin_s", "enabled", "windows"},
                path, warnings);
  }
  if (const YAML::Node e = root["ekf"]) {
    EkfOptions& k = c.ekf;
    read(e, "ekf", "covariance_interval_s", &k.covariance_interval_s, path);
    read(e, "ekf", "record_interval_s", &k.record_interval_s, path);
    read(e, "ekf", "gate_probability", &k.gate_probability, path);
    read(e, "ekf", "max_consecutive_rejections", &k.max_consecutive_rejections, path);
    read(e, "ekf", "gnss_std_scale", &k.gnss_std_scale, path);
    read(e, "ekf", "gnss_std_floor_m", &k.gnss_std_floor_m, path);
    read(e, "ekf", "gnss_default_std_m", &k.gnss_default_std_m, path);
    read(e, "ekf", "init_pos_std_m", &k.init_pos_std_m, path);
    read(e, "ekf", "init_vel_std_m_s", &k.init_vel_std_m_s, path);
    double rp_deg = k.init_roll_pitch_std_rad * units::kRadToDeg;
    double hd_deg = k.init_heading_std_rad * units::kRadToDeg;
    read(e, "ekf", "init_roll_pitch_std_deg", &rp_deg, path);
    read(e, "ekf", "init_heading_std_deg", &hd_deg, path);
    k.init_roll_pitch_std_rad = rp_deg * units::kDegToRad;
    k.init_heading_std_rad = hd_deg * units::kDegToRad;
    read(e, "ekf", "alignment", &c.alignment.mode, path);
    read(e, "ekf", "static_alignment_s", &c.alignment.static_duration_s, path);
    read(e, "ekf", "motion_min_speed_m_s", &c.alignment.motion.min_speed_m_s, path);
    if (c.alignment.mode != "given" && c.alignment.mode != "static" && c.alignment.mode != "motion") {
      throw std::runtime_error(where(path, e["alignment"], "ekf.alignment") + ": '" + c.alignment.mode +
                               "' is not one of given, static, motion");
    }
    try {
      k.validate();
    } catch (const std::invalid_argument& ex) {
      throw std::runtime_error(path + ": section ekf: " + ex.what());
    }
    warnUnknown(e, "ekf",
                {"covariance_interval_s", "record_interval_s", "gate_probability",
                 "max_consecutive_rejections", "gnss_std_scale", "gnss_std_floor_m",
                 "gnss_default_std_m", "init_pos_std_m", "init_vel_std_m_s",
                 "init_roll_pitch_std_deg", "init_heading_std_deg", "alignment",
                 "static_alignment_s", "motion_min_speed_m_s"},
                path, warnings);
  }
  if (const YAML::Node v = root["evaluation"]) {
    read(v, "evaluation", "nees_interval_s", &c.evaluation.options.nees_interval_s, path);
    read(v, "evaluation", "csv_rate_hz", &c.evaluation.csv_rate_hz, path);
    if (!(c.evaluation.csv_rate_hz > 0.0)) {
      throw std::runtime_error(where(path, v["csv_rate_hz"], "evaluation.csv_rate_hz") + ": must be > 0");
    }
    try {
      c.evaluation.options.validate();
    } catch (const std::invalid_argument& ex) {
      throw std::runtime_error(path + ": section evaluation: " + ex.what());
    }
    warnUnknown(v, "evaluation", {"nees_interval_s", "csv_rate_hz"}, path, warnings);
  }
  return c;
}

}  // namespace graftnav::app
