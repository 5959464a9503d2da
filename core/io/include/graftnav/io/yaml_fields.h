#pragma once
// Private helpers of the YAML parsers in core (case_config.cpp, imu_profile_io.cpp): typed field
// access whose errors name the file, line and dotted key, and unknown-key warnings.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace graftnav::yaml_fields {

struct Context {
  std::string path;                             // file, for messages
  std::vector<std::string>* warnings = nullptr;  // unknown keys go here (may be null)
};

inline std::string where(const Context& ctx, const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return ctx.path;
  return ctx.path + ":" + std::to_string(m.line + 1);
}

inline std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

[[noreturn]] inline void fail(const Context& ctx, const YAML::Node& node, const std::string& key, const std::string& what) {
  throw std::runtime_error(where(ctx, node) + ": key '" + key + "': " + what);
}

inline std::string describe(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "nothing";
}

inline YAML::Node requireMap(const Context& ctx, const YAML::Node& parent, const std::string& key_path,
                             const YAML::Node& node) {
  if (!node.IsMap()) fail(ctx, node.IsDefined() ? node : parent, key_path, "expected a map, got " + describe(node));
  return node;
}

inline YAML::Node child(const Context& ctx, const YAML::Node& map, const std::string& prefix, const char* key,
                        bool required) {
  const YAML::Node n = map[key];
  if (required && (!n.IsDefined() || n.IsNull()))
    throw std::runtime_error(where(ctx, map) + ": missing required key '" + join(prefix, key) + "'");
  return n;
}

inline bool present(const YAML::Node& n) { return n.IsDefined() && !n.IsNull(); }

inline double asDouble(const Context& ctx, const YAML::Node& n, const std::string& key_path) {
  double v = 0.0;
  if (!n.IsScalar()) fail(ctx, n, key_path, "expected a number, got " + describe(n));
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(ctx, n, key_path, "expected a number, got " + describe(n));
  }
  if (!std::isfinite(v)) fail(ctx, n, key_path, "expected a finite number, got " + describe(n));
  return v;
}

inline int asInt(const Context& ctx, const YAML::Node& n, const std::string& key_path) {
  const double v = asDouble(ctx, n, key_path);
  if (v != std::floor(v) || std::fabs(v) > 2e9) fail(ctx, n, key_path, "expected an integer, got " + describe(n));
  return static_cast<int>(v);
}

inline bool asBool(const Context& ctx, const YAML::Node& n, const std::string& key_path) {
  if (!n.IsScalar()) fail(ctx, n, key_path, "expected true or false, got " + describe(n));
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    fail(ctx, n, key_path, "expected true or false, got " + describe(n));
  }
}

inline std::string asString(const Context& ctx, const YAML::Node& n, const std::string& key_path) {
  if (!n.IsScalar()) fail(ctx, n, key_path, "expected a string, got " + describe(n));
  return n.Scalar();
}

inline Eigen::Vector3d asVector3(const Context& ctx, const YAML::Node& n, const std::string& key_path) {
  if (!n.IsSequence() || n.size() != 3) fail(ctx, n, key_path, "expected a list of 3 numbers, got " + describe(n));
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = asDouble(ctx, n[i], key_path + "[" + std::to_string(i) + "]");
  return v;
}

inline double requireDouble(const Context& ctx, const YAML::Node& map, const std::string& prefix, const char* key) {
  return asDouble(ctx, child(ctx, map, prefix, key, true), join(prefix, key));
}

inline std::optional<double> optionalDouble(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                                            const char* key) {
  const YAML::Node n = map[key];
  if (!present(n)) return std::nullopt;
  return asDouble(ctx, n, join(prefix, key));
}

// Adds "path:line: unknown key 'prefix.key' ignored" for every key of map not in known.
inline void warnUnknownKeys(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                            std::initializer_list<const char*> known) {
  if (!map.IsMap() || !ctx.warnings) return;
  for (const auto& kv : map) {
    const std::string k = kv.first.Scalar();
    bool found = false;
    for (const char* kn : known) found = found || k == kn;
    if (!found) ctx.warnings->push_back(where(ctx, kv.first) + ": unknown key '" + join(prefix, k) + "' ignored");
  }
}

inline YAML::Node loadFile(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(path + ": cannot open file (missing or unreadable)");
  } catch (const YAML::ParserException& e) {
    throw std::runtime_error(path + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
}

}  // namespace graftnav::yaml_fields
