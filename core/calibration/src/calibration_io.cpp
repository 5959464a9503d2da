#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <stdexcept>

#include "graftnav/calibration/calibration_io.h"
#include "graftnav/io/atomic_file.h"

namespace graftnav {
namespace {

YAML::Node vec3Node(const Eigen::Vector3d& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (int i = 0; i < 3; ++i) n.push_back(v[i]);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node mat3Node(const Eigen::Matrix3d& m) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (int r = 0; r < 3; ++r) n.push_back(vec3Node(m.row(r).transpose()));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node vecNode(const std::vector<double>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (double x : v) n.push_back(x);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node sensorNode(const SensorCalibration& s) {
  YAML::Node n;
  n["method"] = s.method;
  n["M"] = mat3Node(s.M);
  n["bias"] = vec3Node(s.bias);
  n["M_sigma"] = mat3Node(s.M_sigma);
  n["bias_sigma"] = vec3Node(s.bias_sigma);
  if (s.has_allan) {
    n["white_noise"] = vec3Node(s.allan.white_noise);
    n["white_noise_sigma"] = vec3Node(s.allan.white_noise_sigma);
    n["bias_instability"] = vec3Node(s.allan.bias_instability);
    n["bias_instability_sigma"] = vec3Node(s.allan.bias_instability_sigma);
    n["rate_random_walk"] = vec3Node(s.allan.rate_random_walk);
    n["rate_random_walk_sigma"] = vec3Node(s.allan.rate_random_walk_sigma);
  }
  if (s.has_fit) {
    static const char* kAxes[3] = {"x", "y", "z"};
    YAML::Node fit;
    for (int a = 0; a < 3; ++a) {
      YAML::Node f;
      f["degree"] = s.fit[a].degree;
      f["coeffs"] = vecNode(s.fit[a].coeffs);
      f["coeffs_sigma"] = vecNode(s.fit[a].coeffs_sigma);
      if (std::isfinite(s.fit[a].cv_rms)) f["cv_rms"] = s.fit[a].cv_rms;  // absent: not validated
      f["residual_rms"] = s.fit[a].residual_rms;
      f["n_points"] = s.fit[a].n_points;
      if (std::isfinite(s.fit[a].c2_tested)) {  // absent: the points support no quadratic
        f["c2_tested"] = s.fit[a].c2_tested;
        f["c2_tested_sigma"] = s.fit[a].c2_tested_sigma;
      }
      // The fit's response to an asymmetry |x| and a curvature x^2 (absent: not computed).
      for (const auto& [k, v] : {std::make_pair("slope_per_abs", s.fit[a].slope_per_abs),
                                 std::make_pair("slope_per_sq", s.fit[a].slope_per_sq),
                                 std::make_pair("c2_tested_per_abs", s.fit[a].c2_tested_per_abs)})
        if (std::isfinite(v)) f[k] = v;
      fit[kAxes[a]] = f;
    }
    n["fit"] = fit;
  }
  return n;
}

// yaml-cpp writes NaN and inf as .nan / .inf; readCalibrationYaml rejects them, so the writer refuses
// them first, naming the key, rather than leave a file no command can read.
void requireFiniteScalars(const YAML::Node& n, const std::string& key, const std::string& path) {
  if (n.IsScalar()) {
    std::string v = n.Scalar();
    for (char& ch : v) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (!v.empty() && (v[0] == '+' || v[0] == '-')) v.erase(0, 1);
    if (v == ".nan" || v == "nan" || v == ".inf" || v == "inf")
      throw std::runtime_error("writeCalibrationYaml: " + path + ": key '" + key + "' is not finite (" + n.Scalar() +
                               "); refusing to write it");
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) requireFiniteScalars(n[i], key + "[" + std::to_string(i) + "]", path);
  } else if (n.IsMap()) {
    for (const auto& kv : n) {
      const std::string k = kv.first.as<std::string>();
      if (k == "model" || k == "method" || k == "case") continue;  // text
      requireFiniteScalars(kv.second, key.empty() ? k : key + "." + k, path);
    }
  }
}

[[noreturn]] void fail(const std::string& path, const std::string& key, const std::string& why) {
  throw std::runtime_error("readCalibrationYaml: " + path + ": key '" + key + "': " + why);
}

double finite(const YAML::Node& n, const std::string& path, const std::string& key) {
  double v;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(path, key, "not a number");
  }
  if (!std::isfinite(v)) fail(path, key, "not finite");
  return v;
}

Eigen::Vector3d readVec3(const YAML::Node& n, const std::string& path, const std::string& key) {
  if (!n || !n.IsSequence() || n.size() != 3) fail(path, key, "expected a list of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = finite(n[i], path, key);
  return v;
}

Eigen::Matrix3d readMat3(const YAML::Node& n, const std::string& path, const std::string& key) {
  if (!n || !n.IsSequence() || n.size() != 3) fail(path, key, "expected 3 rows of 3 numbers");
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) m.row(r) = readVec3(n[r], path, key).transpose();
  return m;
}

std::vector<double> readVec(const YAML::Node& n, const std::string& path, const std::string& key) {
  if (!n || !n.IsSequence()) fail(path, key, "expected a list of numbers");
  std::vector<double> v;
  for (const auto& e : n) v.push_back(finite(e, path, key));
  return v;
}

SensorCalibration readSensor(const YAML::Node& n, const std::string& path, const std::string& name) {
  if (!n || !n.IsMap()) fail(path, name, "missing sensor section");
  SensorCalibration s;
  if (n["method"]) s.method = n["method"].as<std::string>();
  s.M = readMat3(n["M"], path, name + ".M");
  s.bias = readVec3(n["bias"], path, name + ".bias");
  if (n["M_sigma"]) s.M_sigma = readMat3(n["M_sigma"], path, name + ".M_sigma");
  if (n["bias_sigma"]) s.bias_sigma = readVec3(n["bias_sigma"], path, name + ".bias_sigma");
  if (n["white_noise"]) {
    s.has_allan = true;
    s.allan.white_noise = readVec3(n["white_noise"], path, name + ".white_noise");
    auto opt = [&](const char* key, Eigen::Vector3d& dst) {
      if (n[key]) dst = readVec3(n[key], path, name + "." + key);
    };
    opt("white_noise_sigma", s.allan.white_noise_sigma);
    opt("bias_instability", s.allan.bias_instability);
    opt("bias_instability_sigma", s.allan.bias_instability_sigma);
    opt("rate_random_walk", s.allan.rate_random_walk);
    opt("rate_random_walk_sigma", s.allan.rate_random_walk_sigma);
  }
  if (n["fit"]) {
    s.has_fit = true;
    static const char* kAxes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      const std::string key = name + ".fit." + kAxes[a];
      const YAML::Node f = n["fit"][kAxes[a]];
      if (!f) fail(path, key, "missing axis");
      PolynomialFit& p = s.fit[a];
      p.coeffs = readVec(f["coeffs"], path, key + ".coeffs");
      if (p.coeffs.empty()) fail(path, key + ".coeffs", "empty");
      p.degree = f["degree"] ? f["degree"].as<int>() : static_cast<int>(p.coeffs.size()) - 1;
      if (p.degree != static_cast<int>(p.coeffs.size()) - 1)
        fail(path, key + ".degree", "does not match the number of coefficients");
      if (f["coeffs_sigma"]) p.coeffs_sigma = readVec(f["coeffs_sigma"], path, key + ".coeffs_sigma");
      p.cv_rms = f["cv_rms"] ? finite(f["cv_rms"], path, key + ".cv_rms") : std::nan("");
      if (f["residual_rms"]) p.residual_rms = finite(f["residual_rms"], path, key + ".residual_rms");
      if (f["n_points"]) p.n_points = f["n_points"].as<int>();
      if (f["c2_tested"]) {
        p.c2_tested = finite(f["c2_tested"], path, key + ".c2_tested");
        if (!f["c2_tested_sigma"]) fail(path, key + ".c2_tested_sigma", "missing (c2_tested is given)");
        p.c2_tested_sigma = finite(f["c2_tested_sigma"], path, key + ".c2_tested_sigma");
      }
      for (const auto& [k, v] : {std::make_pair("slope_per_abs", &p.slope_per_abs),
                                 std::make_pair("slope_per_sq", &p.slope_per_sq),
                                 std::make_pair("c2_tested_per_abs", &p.c2_tested_per_abs)})
        if (f[k]) *v = finite(f[k], path, key + "." + k);
    }
  }
  return s;
}

}  // namespace

void writeCalibrationYaml(const std::string& path, const CalibrationResult& result) {
  YAML::Node root;
  root["case"] = result.case_name;
  root["lab_latitude_deg"] = result.lab_latitude_deg;
  root["gravity_m_s2"] = result.gravity_m_s2;
  root["model"] = "measured = M * true + bias; M = I + S + N; SI units (m/s^2, rad/s)";
  root["accel"] = sensorNode(result.accel);
  root["gyro"] = sensorNode(result.gyro);
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << root;
  requireFiniteScalars(root, "", path);
  writeFileAtomically(path, std::string("# graftnav lab calibration (graftnav calibrate); see docs/calibration.md\n") +
                                out.c_str() + "\n");
}

CalibrationResult readCalibrationYaml(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("readCalibrationYaml: " + path + ": " + e.what());
  }
  CalibrationResult r;
  if (root["case"]) r.case_name = root["case"].as<std::string>();
  if (root["lab_latitude_deg"]) r.lab_latitude_deg = finite(root["lab_latitude_deg"], path, "lab_latitude_deg");
  if (root["gravity_m_s2"]) r.gravity_m_s2 = finite(root["gravity_m_s2"], path, "gravity_m_s2");
  r.accel = readSensor(root["accel"], path, "accel");
  r.gyro = readSensor(root["gyro"], path, "gyro");
  return r;
}

}  // namespace graftnav
