#include "graftnav/case/run_config.h"

#include <fmt/core.h>

#include <stdexcept>

#include "graftnav/io/yaml_fields.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace yf = yaml_fields;

using KeyList = std::vector<std::string>;

const KeyList kTimeRangeKeys = {"start_s", "end_s"};
const KeyList kOutagesKeys = {"length_s",     "period_s", "start_s",
                              "end_margin_s", "enabled",  "windows"};
const KeyList kGnssKeys = {"fix_types",    "max_horizontal_std_m",  "max_vertical_std_m",
                           "latency_s",    "latency_s_by_fix_type", "checkpoint_fix_types",
                           "min_spacing_s"};
const KeyList kEkfKeys = {"covariance_interval_s",      "record_interval_s",    "gate_probability",
                          "max_consecutive_rejections", "gnss_std_scale",       "gnss_std_floor_m",
                          "gnss_default_std_m",         "init_pos_std_m",       "init_vel_std_m_s",
                          "init_roll_pitch_std_deg",    "init_heading_std_deg", "alignment",
                          "static_alignment_s",         "motion_min_speed_m_s", "motion_max_std_m"};
const KeyList kGraftingKeys = {"start_offset_s", "realizations", "outage_shifts"};
const KeyList kFgoKeys = {"earth_rotation",
                          "max_node_spacing_s",
                          "reintegrate_gyro_bias_rad_s",
                          "reintegrate_accel_bias_m_s2",
                          "max_reintegration_rounds",
                          "imu_scale_states",
                          "robust_loss",
                          "robust_loss_scale",
                          "chi2_threshold",
                          "culling_rounds",
                          "gnss_min_std_m",
                          "cull_grace_s",
                          "max_consecutive_culls",
                          "max_cull_fraction",
                          "initial_position_std_m",
                          "initial_velocity_std_m_s",
                          "initial_attitude_std_rad",
                          "max_iterations",
                          "num_threads",
                          "compute_covariance",
                          "window_nodes",
                          "window_iterations",
                          "window_solve_stride",
                          "window_fixed_lag_output",
                          "batch_init_stride"};
const KeyList kEvaluationKeys = {"nees_interval_s", "csv_rate_hz"};

// Rethrows an options struct's validate() failure naming the source and section.
template <typename Validate>
void validateSection(const yf::Context& ctx, const char* section, Validate&& validate) {
  try {
    validate();
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(ctx.path + ": section " + section + ": " + ex.what());
  }
}

void parseTimeRange(const yf::Context& ctx, const YAML::Node& t, TimeRangeConfig* r) {
  double v = 0.0;
  if (yf::readOptional(ctx, t, "time_range", "start_s", &v)) r->start_s = v;
  if (yf::readOptional(ctx, t, "time_range", "end_s", &v)) r->end_s = v;
  if (r->start_s && r->end_s && !(*r->end_s > *r->start_s))
    yf::fail(ctx, t, "time_range", "end_s must be > start_s");
  yf::warnUnknownKeys(ctx, t, "time_range", kTimeRangeKeys);
}

void parseOutages(const yf::Context& ctx, const YAML::Node& o, OutageScheduleConfig* s) {
  yf::readOptional(ctx, o, "outages", "length_s", &s->length_s);
  yf::readOptional(ctx, o, "outages", "period_s", &s->period_s);
  yf::readOptional(ctx, o, "outages", "start_s", &s->start_s);
  yf::readOptional(ctx, o, "outages", "end_margin_s", &s->end_margin_s);
  yf::readOptional(ctx, o, "outages", "enabled", &s->enabled);
  if (const YAML::Node w = o["windows"]) {
    if (!w.IsSequence()) yf::fail(ctx, w, "outages.windows", "expected a list of [start, end]");
    s->explicit_windows.clear();
    for (const auto& p : w) {
      if (!p.IsSequence() || p.size() != 2)
        yf::fail(ctx, p, "outages.windows", "each window is [start_s, end_s]");
      const TimeWindow tw{yf::asDouble(ctx, p[0], "outages.windows"),
                          yf::asDouble(ctx, p[1], "outages.windows")};
      if (!(tw.end_s > tw.start_s)) yf::fail(ctx, p, "outages.windows", "start must be < end");
      s->explicit_windows.push_back(tw);
    }
  }
  yf::warnUnknownKeys(ctx, o, "outages", kOutagesKeys);
}

void parseGnss(const yf::Context& ctx, const YAML::Node& g, GnssConfig* q) {
  q->given = true;
  GnssSelectionOptions& sel = q->selection;
  yf::readOptional(ctx, g, "gnss", "fix_types", &sel.accepted_fix_types);
  yf::readOptional(ctx, g, "gnss", "max_horizontal_std_m", &sel.max_horizontal_std_m);
  yf::readOptional(ctx, g, "gnss", "max_vertical_std_m", &sel.max_vertical_std_m);
  yf::readOptional(ctx, g, "gnss", "latency_s", &sel.latency_s);
  yf::readOptional(ctx, g, "gnss", "latency_s_by_fix_type", &sel.latency_s_by_fix_type);
  yf::readOptional(ctx, g, "gnss", "checkpoint_fix_types", &q->checkpoint_fix_types);
  yf::readOptional(ctx, g, "gnss", "min_spacing_s", &sel.min_spacing_s);
  validateSection(ctx, "gnss", [&] { sel.validate(); });
  yf::warnUnknownKeys(ctx, g, "gnss", kGnssKeys);
}

// Reads section.key, a word that `parse` turns into its enum (false for any other text), when the
// key is there; another word fails naming the key and its line, with `complaint(text)` after.
template <typename Enum, typename Parse, typename Complaint>
void readWord(const yf::Context& ctx, const YAML::Node& map, const char* section, const char* key,
              Parse parse, Enum* out, Complaint complaint) {
  if (!map[key].IsDefined()) return;
  std::string text;
  yf::readOptional(ctx, map, section, key, &text);
  if (!parse(text, out)) yf::fail(ctx, map[key], yf::join(section, key), complaint(text));
}

void parseAlignment(const yf::Context& ctx, const YAML::Node& e, AlignmentConfig* a) {
  readWord(ctx, e, "ekf", "alignment", parseAlignmentMode, &a->mode, [](const std::string& text) {
    return "'" + text + "' is not one of given, static, motion";
  });
  yf::readOptional(ctx, e, "ekf", "static_alignment_s", &a->static_duration_s);
  yf::readOptional(ctx, e, "ekf", "motion_min_speed_m_s", &a->motion.min_speed_m_s);
  yf::readOptional(ctx, e, "ekf", "motion_max_std_m", &a->motion_max_std_m);
  if (!(a->motion_max_std_m > 0.0))
    yf::fail(ctx, e["motion_max_std_m"], "ekf.motion_max_std_m", "must be > 0");
}

void parseEkf(const yf::Context& ctx, const YAML::Node& e, EkfOptions* k, AlignmentConfig* a) {
  yf::readOptional(ctx, e, "ekf", "covariance_interval_s", &k->covariance_interval_s);
  yf::readOptional(ctx, e, "ekf", "record_interval_s", &k->record_interval_s);
  yf::readOptional(ctx, e, "ekf", "gate_probability", &k->gate_probability);
  yf::readOptional(ctx, e, "ekf", "max_consecutive_rejections", &k->max_consecutive_rejections);
  yf::readOptional(ctx, e, "ekf", "gnss_std_scale", &k->gnss_std_scale);
  yf::readOptional(ctx, e, "ekf", "gnss_std_floor_m", &k->gnss_std_floor_m);
  yf::readOptional(ctx, e, "ekf", "gnss_default_std_m", &k->gnss_default_std_m);
  yf::readOptional(ctx, e, "ekf", "init_pos_std_m", &k->init_pos_std_m);
  yf::readOptional(ctx, e, "ekf", "init_vel_std_m_s", &k->init_vel_std_m_s);
  double rp_deg = k->init_roll_pitch_std_rad * units::kRadToDeg;
  double hd_deg = k->init_heading_std_rad * units::kRadToDeg;
  yf::readOptional(ctx, e, "ekf", "init_roll_pitch_std_deg", &rp_deg);
  yf::readOptional(ctx, e, "ekf", "init_heading_std_deg", &hd_deg);
  k->init_roll_pitch_std_rad = rp_deg * units::kDegToRad;
  k->init_heading_std_rad = hd_deg * units::kDegToRad;
  parseAlignment(ctx, e, a);
  validateSection(ctx, "ekf", [&] { k->validate(); });
  yf::warnUnknownKeys(ctx, e, "ekf", kEkfKeys);
}

void parseGrafting(const yf::Context& ctx, const YAML::Node& g, GraftingConfig* c) {
  yf::warnUnknownKeys(ctx, g, "grafting", kGraftingKeys);
  yf::readOptional(ctx, g, "grafting", "start_offset_s", &c->start_offset_s);
  yf::readOptional(ctx, g, "grafting", "realizations", &c->realizations);
  yf::readOptional(ctx, g, "grafting", "outage_shifts", &c->outage_shifts);
  if (c->realizations < 1)
    yf::fail(ctx, g["realizations"], "grafting.realizations",
             "must be >= 1, got " + std::to_string(c->realizations));
  if (c->outage_shifts < 1)
    yf::fail(ctx, g["outage_shifts"], "grafting.outage_shifts",
             "must be >= 1, got " + std::to_string(c->outage_shifts));
}

void parseFgo(const yf::Context& ctx, const YAML::Node& g, FgoOptions* f) {
  const auto field = [&](const char* key, auto* out) { yf::readOptional(ctx, g, "fgo", key, out); };
  field("earth_rotation", &f->earth_rotation);
  field("max_node_spacing_s", &f->max_node_spacing_s);
  field("reintegrate_gyro_bias_rad_s", &f->reintegrate_gyro_bias_rad_s);
  field("reintegrate_accel_bias_m_s2", &f->reintegrate_accel_bias_m_s2);
  field("max_reintegration_rounds", &f->max_reintegration_rounds);
  const auto expected = [](const char* words) {
    return [words](const std::string& text) { return "'" + text + "': expected " + words; };
  };
  readWord(ctx, g, "fgo", "imu_scale_states", parseImuScaleStates, &f->imu_scale_states,
           expected("off, with_vehicle_aiding or on"));
  readWord(ctx, g, "fgo", "robust_loss", parseRobustLoss, &f->robust_loss,
           expected("huber, cauchy or none"));
  field("robust_loss_scale", &f->robust_loss_scale);
  field("chi2_threshold", &f->chi2_threshold);
  field("culling_rounds", &f->culling_rounds);
  field("gnss_min_std_m", &f->gnss_min_std_m);
  field("cull_grace_s", &f->cull_grace_s);
  field("max_consecutive_culls", &f->max_consecutive_culls);
  field("max_cull_fraction", &f->max_cull_fraction);
  field("initial_position_std_m", &f->initial_position_std_m);
  field("initial_velocity_std_m_s", &f->initial_velocity_std_m_s);
  field("initial_attitude_std_rad", &f->initial_attitude_std_rad);
  field("max_iterations", &f->max_iterations);
  field("num_threads", &f->num_threads);
  field("compute_covariance", &f->compute_covariance);
  field("window_nodes", &f->window_nodes);
  field("window_iterations", &f->window_iterations);
  field("window_solve_stride", &f->window_solve_stride);
  field("window_fixed_lag_output", &f->window_fixed_lag_output);
  field("batch_init_stride", &f->batch_init_stride);
  std::string err;
  if (!f->validate(&err)) throw std::runtime_error(ctx.path + ": section fgo: " + err);
  yf::warnUnknownKeys(ctx, g, "fgo", kFgoKeys);
}

void parseEvaluation(const yf::Context& ctx, const YAML::Node& v, EvaluationConfig* c) {
  yf::readOptional(ctx, v, "evaluation", "nees_interval_s", &c->options.nees_interval_s);
  yf::readOptional(ctx, v, "evaluation", "csv_rate_hz", &c->csv_rate_hz);
  if (!(c->csv_rate_hz > 0.0))
    yf::fail(ctx, v["csv_rate_hz"], "evaluation.csv_rate_hz", "must be > 0");
  validateSection(ctx, "evaluation", [&] { c->options.validate(); });
  yf::warnUnknownKeys(ctx, v, "evaluation", kEvaluationKeys);
}

// A section given with no value (`ekf:`) is an empty section; anything but a map is an error.
YAML::Node section(const yf::Context& ctx, const YAML::Node& root, const char* key) {
  const YAML::Node s = root[key];
  if (!s.IsDefined() || s.IsNull()) return s.IsDefined() ? YAML::Node(YAML::NodeType::Map) : s;
  return yf::requireMap(ctx, root, key, s);
}

// The same node without source positions: a value given as text has no line worth naming.
YAML::Node withoutMarks(const YAML::Node& n) {
  if (n.IsScalar()) return YAML::Node(n.Scalar());
  YAML::Node out;
  if (n.IsSequence()) {
    out = YAML::Node(YAML::NodeType::Sequence);
    for (const auto& e : n) out.push_back(withoutMarks(e));
  } else if (n.IsMap()) {
    out = YAML::Node(YAML::NodeType::Map);
    for (const auto& kv : n) out[kv.first.Scalar()] = withoutMarks(kv.second);
  }
  return out;
}

}  // namespace

const char* alignmentModeName(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::kGiven:
      return "given";
    case AlignmentMode::kStatic:
      return "static";
    case AlignmentMode::kMotion:
      return "motion";
  }
  return "given";
}

bool parseAlignmentMode(const std::string& text, AlignmentMode* out) {
  for (const AlignmentMode m :
       {AlignmentMode::kGiven, AlignmentMode::kStatic, AlignmentMode::kMotion})
    if (text == alignmentModeName(m)) {
      *out = m;
      return true;
    }
  return false;
}

const std::vector<std::pair<std::string, std::vector<std::string>>>& runConfigSchema() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> schema = {
      {"time_range", kTimeRangeKeys},
      {"outages", kOutagesKeys},
      {"gnss", kGnssKeys},
      {"ekf", kEkfKeys},
      {"grafting", kGraftingKeys},
      {"fgo", kFgoKeys},
      {"evaluation", kEvaluationKeys},
      {"odometer", odometerSectionKeys()},
      {"nhc", nhcSectionKeys()}};
  return schema;
}

RunConfig parseRunConfig(const YAML::Node& root, const std::string& source, RunConfigReport* report,
                         const RunConfig& base) {
  const yf::Context ctx{source, report ? &report->warnings : nullptr,
                        report ? &report->unknown_keys : nullptr};
  RunConfig c = base;
  if (!root || root.IsNull()) return c;
  if (!root.IsMap()) throw std::runtime_error(source + ": the run config must be a YAML map");
  // A peer's set-up given as a run config would otherwise run with every key ignored.
  for (const char* peer_key : {"imupath", "imufile"}) {
    if (root[peer_key]) {
      yf::fail(ctx, root[peer_key], peer_key,
               "this is a KF-GINS / OB_GINS set-up, not a run config; convert it with "
               "`graftnav import kf-gins|ob-gins " +
                   source + " --out CASE`");
    }
  }
  KeyList sections;
  for (const auto& s : runConfigSchema()) sections.push_back(s.first);
  yf::warnUnknownKeys(ctx, root, "", sections);
  if (const YAML::Node t = section(ctx, root, "time_range")) parseTimeRange(ctx, t, &c.time_range);
  if (const YAML::Node o = section(ctx, root, "outages")) {
    c.outages_given = true;
    parseOutages(ctx, o, &c.outages);
  }
  if (const YAML::Node g = section(ctx, root, "gnss")) parseGnss(ctx, g, &c.gnss);
  if (const YAML::Node e = section(ctx, root, "ekf")) parseEkf(ctx, e, &c.ekf, &c.alignment);
  if (const YAML::Node g = section(ctx, root, "grafting")) parseGrafting(ctx, g, &c.grafting);
  if (const YAML::Node g = section(ctx, root, "fgo")) parseFgo(ctx, g, &c.fgo);
  if (const YAML::Node v = section(ctx, root, "evaluation")) parseEvaluation(ctx, v, &c.evaluation);
  const YAML::Node odometer = section(ctx, root, "odometer"), nhc = section(ctx, root, "nhc");
  if (odometer) parseOdometerSection(ctx, odometer, &c.aiding);
  if (nhc) parseNhcSection(ctx, nhc, &c.aiding);
  if (odometer || nhc) validateAidingConfig(ctx, c.aiding);
  return c;
}

RunConfig loadRunConfig(const std::string& path, std::vector<std::string>* warnings) {
  RunConfigReport report;
  RunConfig c = parseRunConfig(yf::loadFile(path), path, &report);
  if (warnings) warnings->insert(warnings->end(), report.warnings.begin(), report.warnings.end());
  return c;
}

RunConfig parseRunConfigText(const std::string& yaml_text, const std::string& source,
                             RunConfigReport* report, const RunConfig& base) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw std::runtime_error(source + ":" + std::to_string(e.mark.line + 1) +
                             ": YAML syntax error: " + e.msg);
  }
  return parseRunConfig(root, source, report, base);
}

RunConfig applyRunConfigOverrides(const RunConfig& base,
                                  const std::vector<RunConfigOverride>& overrides,
                                  const std::string& source, RunConfigReport* report) {
  YAML::Node root(YAML::NodeType::Map);
  for (const auto& [key, value] : overrides) {
    if (key.empty() || key.front() == '.' || key.back() == '.' ||
        key.find("..") != std::string::npos)
      throw std::runtime_error(source + ": override key '" + key +
                               "' is not a dotted key like ekf.gate_probability");
    YAML::Node node = root;
    std::size_t begin = 0;
    for (std::size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', begin)) {
      const std::string part = key.substr(begin, dot - begin);
      if (node[part] && !node[part].IsMap())
        throw std::runtime_error(source + ": override key '" + key + "': '" + part +
                                 "' is given a value and keys at once");
      if (!node[part]) node[part] = YAML::Node(YAML::NodeType::Map);
      node.reset(node[part]);
      begin = dot + 1;
    }
    node[key.substr(begin)] = value;
  }
  return parseRunConfig(root, source, report, base);
}

RunConfig applyRunConfigOverrides(const RunConfig& base,
                                  const std::vector<std::pair<std::string, std::string>>& overrides,
                                  const std::string& source, RunConfigReport* report) {
  std::vector<RunConfigOverride> nodes;
  for (const auto& [key, text] : overrides) {
    try {
      nodes.emplace_back(key, withoutMarks(YAML::Load(text)));
    } catch (const YAML::ParserException& e) {
      throw std::runtime_error(source + ": key '" + key + "': '" + text +
                               "' is not a YAML value: " + e.msg);
    }
  }
  return applyRunConfigOverrides(base, nodes, source, report);
}

TimeRangeConfig mergeTimeRange(const TimeRangeConfig& from_config,
                               const TimeRangeConfig& from_cli) {
  TimeRangeConfig r = from_config;
  if (from_cli.start_s) r.start_s = from_cli.start_s;
  if (from_cli.end_s) r.end_s = from_cli.end_s;
  if (r.start_s && r.end_s && !(*r.end_s > *r.start_s)) {
    throw std::runtime_error(
        fmt::format("time range: end {} must be after start {}", *r.end_s, *r.start_s));
  }
  return r;
}

void requireTimeRangeUnset(const TimeRangeConfig& range, const std::string& source,
                           const std::string& command) {
  if (range.empty()) return;
  std::string bounds;
  if (range.start_s) bounds = fmt::format("start_s {}", *range.start_s);
  if (range.end_s) bounds += fmt::format("{}end_s {}", bounds.empty() ? "" : ", ", *range.end_s);
  throw std::runtime_error(fmt::format(
      "time_range is not applied by {}: the run config '{}' sets time_range ({}); remove it to "
      "run on the whole recording (graftnav navigate, compare and real without a latency study apply "
      "it)",
      command, source, bounds));
}

}  // namespace graftnav
