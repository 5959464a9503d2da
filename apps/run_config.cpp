#include "run_config.h"

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>

#include "graftnav/nav/units.h"

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
  // A peer's set-up given as a run config would otherwise run with every key ignored.
  for (const char* peer_key : {"imupath", "imufile"}) {
    if (root[peer_key]) {
      throw std::runtime_error(where(path, root[peer_key], peer_key) +
                               ": this is a KF-GINS / OB_GINS set-up, not a run config; convert it with "
                               "`graftnav import kf-gins|ob-gins " + path + " --out CASE`");
    }
  }
  warnUnknown(root, "", {"time_range", "outages", "ekf", "evaluation", "fgo", "gnss", "grafting"}, path,
              warnings);

  if (const YAML::Node t = root["time_range"]) {
    auto bound = [&](const char* key, std::optional<double>* out) {
      if (!t[key]) return;
      double v = 0.0;
      read(t, "time_range", key, &v, path);
      *out = v;
    };
    bound("start_s", &c.time_range.start_s);
    bound("end_s", &c.time_range.end_s);
    if (c.time_range.start_s && c.time_range.end_s && !(*c.time_range.end_s > *c.time_range.start_s)) {
      throw std::runtime_error(where(path, t, "time_range") + ": end_s must be > start_s");
    }
    warnUnknown(t, "time_range", {"start_s", "end_s"}, path, warnings);
  }

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
  if (const YAML::Node g = root["gnss"]) {
    GnssConfig& q = c.gnss;
    q.given = true;
    read(g, "gnss", "fix_types", &q.selection.accepted_fix_types, path);
    read(g, "gnss", "max_horizontal_std_m", &q.selection.max_horizontal_std_m, path);
    read(g, "gnss", "max_vertical_std_m", &q.selection.max_vertical_std_m, path);
    read(g, "gnss", "latency_s", &q.selection.latency_s, path);
    read(g, "gnss", "latency_s_by_fix_type", &q.selection.latency_s_by_fix_type, path);
    read(g, "gnss", "checkpoint_fix_types", &q.checkpoint_fix_types, path);
    read(g, "gnss", "min_spacing_s", &q.selection.min_spacing_s, path);
    try {
      q.selection.validate();
    } catch (const std::invalid_argument& ex) {
      throw std::runtime_error(path + ": section gnss: " + ex.what());
    }
    warnUnknown(g, "gnss",
                {"fix_types", "max_horizontal_std_m", "max_vertical_std_m", "latency_s",
                 "latency_s_by_fix_type", "checkpoint_fix_types", "min_spacing_s"},
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
    read(e, "ekf", "motion_max_std_m", &c.alignment.motion_max_std_m, path);
    if (!(c.alignment.motion_max_std_m > 0.0)) {
      throw std::runtime_error(where(path, e["motion_max_std_m"], "ekf.motion_max_std_m") + ": must be > 0");
    }
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
                 "static_alignment_s", "motion_min_speed_m_s", "motion_max_std_m"},
                path, warnings);
  }
  if (const YAML::Node g = root["grafting"]) {
    warnUnknown(g, "grafting", {"start_offset_s", "realizations", "outage_shifts"}, path, warnings);
    read(g, "grafting", "start_offset_s", &c.grafting.start_offset_s, path);
    read(g, "grafting", "realizations", &c.grafting.realizations, path);
    read(g, "grafting", "outage_shifts", &c.grafting.outage_shifts, path);
    for (const char* key : {"realizations", "outage_shifts"}) {
      const int v = std::string(key) == "realizations" ? c.grafting.realizations : c.grafting.outage_shifts;
      if (v < 1) throw std::runtime_error(where(path, g[key], std::string("grafting.") + key) + ": must be >= 1, got " + std::to_string(v));
    }
  }
  if (const YAML::Node g = root["fgo"]) {
    FgoOptions& f = c.fgo;
    read(g, "fgo", "earth_rotation", &f.earth_rotation, path);
    read(g, "fgo", "max_node_spacing_s", &f.max_node_spacing_s, path);
    read(g, "fgo", "reintegrate_gyro_bias_rad_s", &f.reintegrate_gyro_bias_rad_s, path);
    read(g, "fgo", "reintegrate_accel_bias_m_s2", &f.reintegrate_accel_bias_m_s2, path);
    read(g, "fgo", "max_reintegration_rounds", &f.max_reintegration_rounds, path);
    read(g, "fgo", "robust_loss", &f.robust_loss, path);
    read(g, "fgo", "robust_loss_scale", &f.robust_loss_scale, path);
    read(g, "fgo", "chi2_threshold", &f.chi2_threshold, path);
    read(g, "fgo", "culling_rounds", &f.culling_rounds, path);
    read(g, "fgo", "gnss_min_std_m", &f.gnss_min_std_m, path);
    read(g, "fgo", "cull_grace_s", &f.cull_grace_s, path);
    read(g, "fgo", "max_consecutive_culls", &f.max_consecutive_culls, path);
    read(g, "fgo", "max_cull_fraction", &f.max_cull_fraction, path);
    read(g, "fgo", "initial_position_std_m", &f.initial_position_std_m, path);
    read(g, "fgo", "initial_velocity_std_m_s", &f.initial_velocity_std_m_s, path);
    read(g, "fgo", "initial_attitude_std_rad", &f.initial_attitude_std_rad, path);
    read(g, "fgo", "max_iterations", &f.max_iterations, path);
    read(g, "fgo", "num_threads", &f.num_threads, path);
    read(g, "fgo", "compute_covariance", &f.compute_covariance, path);
    read(g, "fgo", "window_nodes", &f.window_nodes, path);
    read(g, "fgo", "window_iterations", &f.window_iterations, path);
    read(g, "fgo", "window_solve_stride", &f.window_solve_stride, path);
    read(g, "fgo", "window_fixed_lag_output", &f.window_fixed_lag_output, path);
    read(g, "fgo", "batch_init_stride", &f.batch_init_stride, path);
    std::string err;
    if (!f.validate(&err)) throw std::runtime_error(path + ": section fgo: " + err);
    warnUnknown(g, "fgo",
                {"earth_rotation", "max_node_spacing_s", "reintegrate_gyro_bias_rad_s",
                 "reintegrate_accel_bias_m_s2", "max_reintegration_rounds", "robust_loss",
                 "robust_loss_scale", "chi2_threshold", "culling_rounds", "gnss_min_std_m",
                 "cull_grace_s", "max_consecutive_culls", "max_cull_fraction",
                 "initial_position_std_m", "initial_velocity_std_m_s", "initial_attitude_std_rad",
                 "max_iterations", "num_threads", "compute_covariance", "window_nodes",
                 "window_iterations", "window_solve_stride", "window_fixed_lag_output",
                 "batch_init_stride"},
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
