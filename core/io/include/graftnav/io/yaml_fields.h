#pragma once
// The one YAML field helper of every configuration reader (case.yaml, IMU profiles, simulation
// configs, calibration files, run configs, batch manifests): typed field access whose errors name
// the file, line and dotted key, and unknown-key warnings.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cmath>
#include <initializer_list>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include "graftnav/io/file_errors.h"

namespace graftnav::yaml_fields {

struct Context {
  std::string path;                              // file, for messages
  std::vector<std::string>* warnings = nullptr;  // unknown keys go here (may be null)
  // The unknown keys themselves, dotted ("ekf.gate"), for a caller that refuses them (may be null).
  std::vector<std::string>* unknown_keys = nullptr;
};

inline std::string where(const Context& ctx, const YAML::Node& node) {
  if (!node.IsDefined()) return ctx.path;  // a missing key's zombie node has no position
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return ctx.path;
  return ctx.path + ":" + std::to_string(m.line + 1);
}

inline std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

[[noreturn]] inline void fail(const Context& ctx, const YAML::Node& node, const std::string& key,
                              const std::string& what) {
  throw std::runtime_error(where(ctx, node) + ": key '" + key + "': " + what);
}

inline std::string describe(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "nothing";
}

inline YAML::Node requireMap(const Context& ctx, const YAML::Node& parent,
                             const std::string& key_path, const YAML::Node& node) {
  if (!node.IsMap())
    fail(ctx, node.IsDefined() ? node : parent, key_path, "expected a map, got " + describe(node));
  return node;
}

inline YAML::Node child(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                        const char* key, bool required) {
  const YAML::Node n = map[key];
  if (required && (!n.IsDefined() || n.IsNull()))
    throw std::runtime_error(where(ctx, map) + ": missing required key '" + join(prefix, key) +
                             "'");
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
  if (v != std::floor(v) || std::fabs(v) > 2e9)
    fail(ctx, n, key_path, "expected an integer, got " + describe(n));
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

inline Eigen::Vector3d asVector3(const Context& ctx, const YAML::Node& n,
                                 const std::string& key_path) {
  if (!n.IsSequence() || n.size() != 3)
    fail(ctx, n, key_path, "expected a list of 3 numbers, got " + describe(n));
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = asDouble(ctx, n[i], key_path + "[" + std::to_string(i) + "]");
  return v;
}

inline unsigned long long asUint64(const Context& ctx, const YAML::Node& n,
                                   const std::string& key_path) {
  if (!n.IsScalar()) fail(ctx, n, key_path, "expected a non-negative integer, got " + describe(n));
  const std::string& text = n.Scalar();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    fail(ctx, n, key_path, "expected a non-negative integer, got " + describe(n));
  try {
    return n.as<unsigned long long>();
  } catch (const YAML::Exception&) {
    fail(ctx, n, key_path, "expected a non-negative integer, got " + describe(n));
  }
}

// A list of finite numbers; `size` >= 0 requires exactly that many.
inline std::vector<double> asDoubleList(const Context& ctx, const YAML::Node& n,
                                        const std::string& key_path, int size = -1) {
  if (!n.IsSequence()) fail(ctx, n, key_path, "expected a list of numbers, got " + describe(n));
  if (size >= 0 && static_cast<int>(n.size()) != size)
    fail(ctx, n, key_path,
         "expected " + std::to_string(size) + " numbers, got " + std::to_string(n.size()));
  std::vector<double> v;
  for (std::size_t i = 0; i < n.size(); ++i)
    v.push_back(asDouble(ctx, n[i], key_path + "[" + std::to_string(i) + "]"));
  return v;
}

inline std::vector<int> asIntList(const Context& ctx, const YAML::Node& n,
                                  const std::string& key_path) {
  if (!n.IsSequence()) fail(ctx, n, key_path, "expected a list of integers, got " + describe(n));
  std::vector<int> v;
  for (std::size_t i = 0; i < n.size(); ++i)
    v.push_back(asInt(ctx, n[i], key_path + "[" + std::to_string(i) + "]"));
  return v;
}

// A map from integer keys to finite numbers ({4: 0.1, 5: 0.2}).
inline std::map<int, double> asIntDoubleMap(const Context& ctx, const YAML::Node& n,
                                            const std::string& key_path) {
  if (!n.IsMap())
    fail(ctx, n, key_path, "expected a map of integer keys to numbers, got " + describe(n));
  std::map<int, double> m;
  for (const auto& kv : n) {
    const int k = asInt(ctx, kv.first, key_path + " key");
    m[k] = asDouble(ctx, kv.second, key_path + "." + kv.first.Scalar());
  }
  return m;
}

// The typed conversions `readOptional` can fill.
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    double* out) {
  *out = asDouble(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    int* out) {
  *out = asInt(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    bool* out) {
  *out = asBool(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    std::string* out) {
  *out = asString(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    unsigned long long* out) {
  *out = asUint64(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    std::vector<int>* out) {
  *out = asIntList(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    std::vector<double>* out) {
  *out = asDoubleList(ctx, n, key_path);
}
inline void convert(const Context& ctx, const YAML::Node& n, const std::string& key_path,
                    std::map<int, double>* out) {
  *out = asIntDoubleMap(ctx, n, key_path);
}

// Fills *out from map[key] when the key is there (a key given without a value is an error, not a
// default); returns whether it was.
template <typename T>
bool readOptional(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                  const char* key, T* out) {
  const YAML::Node n = map[key];
  if (!n.IsDefined()) return false;
  convert(ctx, n, join(prefix, key), out);
  return true;
}

inline double requireDouble(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                            const char* key) {
  return asDouble(ctx, child(ctx, map, prefix, key, true), join(prefix, key));
}

inline std::optional<double> optionalDouble(const Context& ctx, const YAML::Node& map,
                                            const std::string& prefix, const char* key) {
  const YAML::Node n = map[key];
  if (!present(n)) return std::nullopt;
  return asDouble(ctx, n, join(prefix, key));
}

// Adds "path:line: unknown key 'prefix.key' ignored" for every key of map not in known (and the
// dotted key to ctx.unknown_keys).
// `known` is a braced list of names or any container of strings.
template <typename Known = std::initializer_list<const char*>>
void warnUnknownKeys(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                     const Known& known) {
  if (!map.IsMap() || (!ctx.warnings && !ctx.unknown_keys)) return;
  for (const auto& kv : map) {
    const std::string k = kv.first.Scalar();
    bool found = false;
    for (const auto& kn : known) found = found || k == kn;
    if (found) continue;
    if (ctx.warnings)
      ctx.warnings->push_back(where(ctx, kv.first) + ": unknown key '" + join(prefix, k) +
                              "' ignored");
    if (ctx.unknown_keys) ctx.unknown_keys->push_back(join(prefix, k));
  }
}

inline YAML::Node loadFile(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw MissingFileError(path, path + ": cannot open file (missing or unreadable)");
  } catch (const YAML::ParserException& e) {
    throw std::runtime_error(path + ":" + std::to_string(e.mark.line + 1) +
                             ": YAML syntax error: " + e.msg);
  }
}

}  // namespace graftnav::yaml_fields
