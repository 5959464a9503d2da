#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <stdexcept>

#include "graftnav/calibration/calibration_io.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/yaml_fields.h"

namespace graftnav {
namespace {

namespace yf = yaml_fields;

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
      throw std::runtime_error("writeCalibrationYaml: " + path + ": key '" + key +
                               "' is not finite (" + n.Scalar() + "); refusing to write it");
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i)
      requireFiniteScalars(n[i], key + "[" + std::to_string(i) + "]", path);
  } else if (n.IsMap()) {
    for (const auto& kv : n) {
      const std::string k = kv.first.as<std::string>();
      if (k == "model" || k == "method" || k == "case") continue;  // text
      requireFiniteScalars(kv.second, key.empty() ? k : key + "." + k, path);
    }
  }
}

Eigen::Matrix3d asMat3(const yf::Context& ctx, const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3)
    yf::fail(ctx, n, key, "expected 3 rows of 3 numbers, got " + yf::describe(n));
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    m.row(r) = yf::asVector3(ctx, n[r], key + "[" + std::to_string(r) + "]").transpose();
  return m;
}

// Keys the Allan section may carry beside white_noise.
void readAllan(const yf::Context& ctx, const YAML::Node& n, const std::string& name,
               AllanTerms* allan) {
  allan->white_noise = yf::asVector3(ctx, n["white_noise"], name + ".white_noise");
  for (const auto& [key, dst] :
       {std::make_pair("white_noise_sigma", &allan->white_noise_sigma),
        std::make_pair("bias_instability", &allan->bias_instability),
        std::make_pair("bias_instability_sigma", &allan->bias_instability_sigma),
        std::make_pair("rate_random_walk", &allan->rate_random_walk),
        std::make_pair("rate_random_walk_sigma", &allan->rate_random_walk_sigma)}) {
    if (n[key]) *dst = yf::asVector3(ctx, n[key], name + "." + key);
  }
}

PolynomialFit readFitAxis(const yf::Context& ctx, const YAML::Node& f, const std::string& key) {
  PolynomialFit p;
  p.coeffs = yf::asDoubleList(ctx, yf::child(ctx, f, key, "coeffs", true), key + ".coeffs");
  if (p.coeffs.empty()) yf::fail(ctx, f["coeffs"], key + ".coeffs", "empty");
  p.degree = static_cast<int>(p.coeffs.size()) - 1;
  int degree = p.degree;
  if (yf::readOptional(ctx, f, key, "degree", &degree) && degree != p.degree)
    yf::fail(ctx, f["degree"], key + ".degree", "does not match the number of coefficients");
  yf::readOptional(ctx, f, key, "coeffs_sigma", &p.coeffs_sigma);
  p.cv_rms = std::nan("");
  yf::readOptional(ctx, f, key, "cv_rms", &p.cv_rms);
  yf::readOptional(ctx, f, key, "residual_rms", &p.residual_rms);
  yf::readOptional(ctx, f, key, "n_points", &p.n_points);
  if (yf::readOptional(ctx, f, key, "c2_tested", &p.c2_tested)) {
    if (!f["c2_tested_sigma"])
      yf::fail(ctx, f, key + ".c2_tested_sigma", "missing (c2_tested is given)");
    yf::readOptional(ctx, f, key, "c2_tested_sigma", &p.c2_tested_sigma);
  }
  yf::readOptional(ctx, f, key, "slope_per_abs", &p.slope_per_abs);
  yf::readOptional(ctx, f, key, "slope_per_sq", &p.slope_per_sq);
  yf::readOptional(ctx, f, key, "c2_tested_per_abs", &p.c2_tested_per_abs);
  return p;
}

SensorCalibration readSensor(const yf::Context& ctx, const YAML::Node& root, const char* name) {
  const YAML::Node n = yf::child(ctx, root, "", name, true);
  yf::requireMap(ctx, root, name, n);
  SensorCalibration s;
  yf::readOptional(ctx, n, name, "method", &s.method);
  s.M = asMat3(ctx, yf::child(ctx, n, name, "M", true), std::string(name) + ".M");
  s.bias = yf::asVector3(ctx, yf::child(ctx, n, name, "bias", true), std::string(name) + ".bias");
  if (n["M_sigma"]) s.M_sigma = asMat3(ctx, n["M_sigma"], std::string(name) + ".M_sigma");
  if (n["bias_sigma"])
    s.bias_sigma = yf::asVector3(ctx, n["bias_sigma"], std::string(name) + ".bias_sigma");
  if (n["white_noise"]) {
    s.has_allan = true;
    readAllan(ctx, n, name, &s.allan);
  }
  if (const YAML::Node fit = n["fit"]) {
    s.has_fit = true;
    const std::string fit_key = std::string(name) + ".fit";
    static const char* kAxes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      s.fit[a] =
          readFitAxis(ctx, yf::child(ctx, fit, fit_key, kAxes[a], true), fit_key + "." + kAxes[a]);
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
  writeFileAtomically(
      path,
      std::string("# graftnav lab calibration (graftnav calibrate); see docs/calibration.md\n") +
          out.c_str() + "\n");
}

CalibrationResult readCalibrationYaml(const std::string& path) {
  const yf::Context ctx{path, nullptr};
  const YAML::Node root = yf::loadFile(path);
  if (!root.IsMap()) throw std::runtime_error(path + ": a calibration file must be a YAML map");
  CalibrationResult r;
  yf::readOptional(ctx, root, "", "case", &r.case_name);
  yf::readOptional(ctx, root, "", "lab_latitude_deg", &r.lab_latitude_deg);
  yf::readOptional(ctx, root, "", "gravity_m_s2", &r.gravity_m_s2);
  r.accel = readSensor(ctx, root, "accel");
  r.gyro = readSensor(ctx, root, "gyro");
  return r;
}

}  // namespace graftnav
