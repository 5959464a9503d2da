#include "graftnav/io/case_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"
#include "graftnav/io/yaml_fields.h"

namespace graftnav {

namespace yf = yaml_fields;
namespace fs = std::filesystem;

namespace {

constexpr const char* kSixPoses[] = {"x_up", "x_down", "y_up", "y_down", "z_up", "z_down"};

Eigen::Vector3d eulerDegToRad(const yf::Context& ctx, const YAML::Node& n, const std::string& key) {
  return yf::asVector3(ctx, n, key) * units::kDegToRad;
}

std::map<std::string, Eigen::Vector3d> parseAttitudeMap(const yf::Context& ctx, const YAML::Node& n,
                                                        const std::string& key) {
  std::map<std::string, Eigen::Vector3d> out;
  if (!yf::present(n)) return out;
  if (!n.IsMap())
    yf::fail(ctx, n, key, "expected a map name: [roll, pitch, yaw] (deg), got " + yf::describe(n));
  for (const auto& kv : n) {
    const std::string name = kv.first.Scalar();
    out[name] = eulerDegToRad(ctx, kv.second, key + "." + name);
  }
  return out;
}

LabConfig parseLab(const yf::Context& ctx, const YAML::Node& lab) {
  yf::warnUnknownKeys(ctx, lab, "lab",
                      {"latitude_deg", "height_m", "static", "six_position", "rate_table", "tilt"});
  LabConfig out;
  const double lat_deg = yf::requireDouble(ctx, lab, "lab", "latitude_deg");
  if (std::fabs(lat_deg) > 90.0)
    yf::fail(ctx, lab["latitude_deg"], "lab.latitude_deg", "must be within [-90, 90]");
  out.latitude_rad = lat_deg * units::kDegToRad;
  out.height_m = yf::requireDouble(ctx, lab, "lab", "height_m");
  const YAML::Node st = lab["static"];
  if (yf::present(st)) {
    yf::requireMap(ctx, lab, "lab.static", st);
    yf::warnUnknownKeys(ctx, st, "lab.static", {"attitude_deg"});
    out.static_euler_rad = eulerDegToRad(
        ctx, yf::child(ctx, st, "lab.static", "attitude_deg", true), "lab.static.attitude_deg");
  }
  out.six_position_euler_rad = parseAttitudeMap(ctx, lab["six_position"], "lab.six_position");
  for (const auto& kv : out.six_position_euler_rad) {
    if (std::find_if(std::begin(kSixPoses), std::end(kSixPoses),
                     [&](const char* p) { return kv.first == p; }) == std::end(kSixPoses))
      yf::fail(ctx, lab["six_position"], "lab.six_position." + kv.first,
               "not a pose name (expected x_up, x_down, y_up, y_down, z_up or z_down)");
  }
  const YAML::Node rt = lab["rate_table"];
  if (yf::present(rt)) {
    yf::requireMap(ctx, lab, "lab.rate_table", rt);
    yf::warnUnknownKeys(ctx, rt, "lab.rate_table", {"axis_up"});
    if (yf::present(rt["axis_up"]))
      out.rate_table_axis_up = yf::asBool(ctx, rt["axis_up"], "lab.rate_table.axis_up");
  }
  out.tilt_euler_rad = parseAttitudeMap(ctx, lab["tilt"], "lab.tilt");
  return out;
}

NavState parseInitialState(const yf::Context& ctx, const YAML::Node& n, int week) {
  yf::warnUnknownKeys(ctx, n, "initial_state",
                      {"time", "position", "velocity_ned", "attitude_deg"});
  NavState s;
  s.gnss_week = week;
  s.t_s = yf::requireDouble(ctx, n, "initial_state", "time");
  const Eigen::Vector3d pos = yf::asVector3(
      ctx, yf::child(ctx, n, "initial_state", "position", true), "initial_state.position");
  if (std::fabs(pos.x()) > 90.0)
    yf::fail(ctx, n["position"], "initial_state.position", "latitude outside [-90, 90] deg");
  s.pos = Geodetic{pos.x() * units::kDegToRad, pos.y() * units::kDegToRad, pos.z()};
  s.v_n = yf::asVector3(ctx, yf::child(ctx, n, "initial_state", "velocity_ned", true),
                        "initial_state.velocity_ned");
  s.q_nb = quatFromEuler(eulerDegToRad(
      ctx, yf::child(ctx, n, "initial_state", "attitude_deg", true), "initial_state.attitude_deg"));
  return s;
}

}  // namespace

CaseConfig loadCaseConfig(const std::string& path, std::vector<std::string>* warnings) {
  return parseCaseConfig(yf::loadFile(path), path, warnings);
}

CaseConfig parseCaseConfig(const YAML::Node& root, const std::string& path,
                           std::vector<std::string>* warnings) {
  const yf::Context ctx{path, warnings};
  if (!root.IsMap()) throw std::runtime_error(path + ": expected a YAML map at the top level");
  yf::warnUnknownKeys(
      ctx, root, "",
      {"name", "imu_rate_hz", "tested_imu_rate_hz", "reference_solution", "reference_imu",
       "tested_imu", "lever_arm_m", "gnss", "initial_state", "lab"});
  CaseConfig c;
  c.name = yf::asString(ctx, yf::child(ctx, root, "", "name", true), "name");
  if (c.name.empty()) yf::fail(ctx, root["name"], "name", "must not be empty");
  c.imu_rate_hz = yf::requireDouble(ctx, root, "", "imu_rate_hz");
  if (!(c.imu_rate_hz > 0.0)) yf::fail(ctx, root["imu_rate_hz"], "imu_rate_hz", "must be > 0");
  c.tested_imu_rate_hz = yf::optionalDouble(ctx, root, "", "tested_imu_rate_hz");
  if (c.tested_imu_rate_hz && !(*c.tested_imu_rate_hz > 0.0))
    yf::fail(ctx, root["tested_imu_rate_hz"], "tested_imu_rate_hz", "must be > 0");
  if (yf::present(root["reference_solution"]))
    c.reference_solution = yf::asString(ctx, root["reference_solution"], "reference_solution");
  for (const char* key : {"reference_imu", "tested_imu"}) {
    const YAML::Node n = root[key];
    if (!yf::present(n)) continue;
    const ImuProfileParse p = parseImuProfileNode(n, path, key, false, warnings);
    if (std::string(key) == "reference_imu") {
      c.reference_imu = p.profile;
      c.reference_imu_noise_given = p.noise_given;
    } else {
      c.tested_imu = p.profile;
      c.tested_imu_noise_given = p.noise_given;
    }
  }
  if (yf::present(root["lever_arm_m"]))
    c.lever_arm_m = yf::asVector3(ctx, root["lever_arm_m"], "lever_arm_m");
  const YAML::Node gnss = root["gnss"];
  if (yf::present(gnss)) {
    yf::requireMap(ctx, root, "gnss", gnss);
    yf::warnUnknownKeys(ctx, gnss, "gnss", {"week"});
    c.gnss_week = yf::asInt(ctx, yf::child(ctx, gnss, "gnss", "week", true), "gnss.week");
    if (*c.gnss_week < 0) yf::fail(ctx, gnss["week"], "gnss.week", "must be >= 0");
  }
  const YAML::Node init = root["initial_state"];
  if (yf::present(init)) {
    yf::requireMap(ctx, root, "initial_state", init);
    c.initial_state = parseInitialState(ctx, init, c.gnss_week.value_or(0));
  }
  const YAML::Node lab = root["lab"];
  if (yf::present(lab)) {
    yf::requireMap(ctx, root, "lab", lab);
    c.lab = parseLab(ctx, lab);
  }
  return c;
}

namespace {
void emitVec(YAML::Emitter& out, const Eigen::Vector3d& v) {
  out << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << v.z() << YAML::EndSeq;
}
Eigen::Vector3d eulerDeg(const Eigen::Vector3d& e_rad) { return e_rad * units::kRadToDeg; }
void emitAttitudeMap(YAML::Emitter& out, const std::map<std::string, Eigen::Vector3d>& m) {
  out << YAML::BeginMap;
  for (const auto& kv : m) {
    out << YAML::Key << kv.first << YAML::Value;
    emitVec(out, eulerDeg(kv.second));
  }
  out << YAML::EndMap;
}
}  // namespace

void saveCaseConfig(const std::string& path, const CaseConfig& c) {
  if (c.name.empty()) throw std::invalid_argument(path + ": saveCaseConfig: empty name");
  if (!(c.imu_rate_hz > 0.0))
    throw std::invalid_argument(path + ": saveCaseConfig: imu_rate_hz must be > 0");
  YAML::Emitter out;
  out.SetDoublePrecision(15);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << c.name;
  out << YAML::Key << "imu_rate_hz" << YAML::Value << c.imu_rate_hz;
  if (c.tested_imu_rate_hz)
    out << YAML::Key << "tested_imu_rate_hz" << YAML::Value << *c.tested_imu_rate_hz;
  if (c.reference_solution)
    out << YAML::Key << "reference_solution" << YAML::Value << *c.reference_solution;
  if (c.reference_imu) {
    out << YAML::Key << "reference_imu" << YAML::Value;
    emitImuProfile(out, *c.reference_imu, c.reference_imu_noise_given);
  }
  if (c.tested_imu) {
    out << YAML::Key << "tested_imu" << YAML::Value;
    emitImuProfile(out, *c.tested_imu, c.tested_imu_noise_given);
  }
  if (c.lever_arm_m) {
    out << YAML::Key << "lever_arm_m" << YAML::Value;
    emitVec(out, *c.lever_arm_m);
  }
  if (c.gnss_week) {
    out << YAML::Key << "gnss" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "week"
        << YAML::Value << *c.gnss_week << YAML::EndMap;
  }
  if (c.initial_state) {
    const NavState& s = *c.initial_state;
    out << YAML::Key << "initial_state" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "time" << YAML::Value << s.t_s;
    out << YAML::Key << "position" << YAML::Value;
    emitVec(out, Eigen::Vector3d(s.pos.lat_rad * units::kRadToDeg, s.pos.lon_rad * units::kRadToDeg,
                                 s.pos.h_m));
    out << YAML::Key << "velocity_ned" << YAML::Value;
    emitVec(out, s.v_n);
    out << YAML::Key << "attitude_deg" << YAML::Value;
    emitVec(out, eulerDeg(eulerFromQuat(s.q_nb.normalized())));
    out << YAML::EndMap;
  }
  if (c.lab) {
    const LabConfig& lab = *c.lab;
    out << YAML::Key << "lab" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "latitude_deg" << YAML::Value << lab.latitude_rad * units::kRadToDeg;
    out << YAML::Key << "height_m" << YAML::Value << lab.height_m;
    if (lab.static_euler_rad) {
      out << YAML::Key << "static" << YAML::Value << YAML::BeginMap << YAML::Key << "attitude_deg"
          << YAML::Value;
      emitVec(out, eulerDeg(*lab.static_euler_rad));
      out << YAML::EndMap;
    }
    if (!lab.six_position_euler_rad.empty()) {
      out << YAML::Key << "six_position" << YAML::Value;
      emitAttitudeMap(out, lab.six_position_euler_rad);
    }
    if (lab.rate_table_axis_up) {
      out << YAML::Key << "rate_table" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
          << "axis_up" << YAML::Value << *lab.rate_table_axis_up << YAML::EndMap;
    }
    if (!lab.tilt_euler_rad.empty()) {
      out << YAML::Key << "tilt" << YAML::Value;
      emitAttitudeMap(out, lab.tilt_euler_rad);
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  if (!out.good()) throw std::runtime_error(path + ": YAML emitter error: " + out.GetLastError());
  writeFileAtomically(path, std::string(out.c_str()) + "\n");
}

double RateFile::rate_rad_s() const { return sign * rate_deg_s * units::kDegToRad; }

CasePaths::CasePaths(std::string case_dir) : dir_(std::move(case_dir)) {}
std::string CasePaths::caseYaml() const { return (fs::path(dir_) / "case.yaml").string(); }
std::string CasePaths::refImu() const {
  return (fs::path(dir_) / "field" / "ref_imu.txt").string();
}
std::string CasePaths::testedImu() const {
  return (fs::path(dir_) / "field" / "tested_imu.txt").string();
}
std::string CasePaths::gnssPos() const { return (fs::path(dir_) / "field" / "gnss.pos").string(); }
std::string CasePaths::gnssFixType() const {
  return (fs::path(dir_) / "field" / "gnss_fixtype.txt").string();
}
std::string CasePaths::odometer() const {
  return (fs::path(dir_) / "field" / "odometer.txt").string();
}
std::string CasePaths::truthNav() const {
  return (fs::path(dir_) / "field" / "truth.nav").string();
}
std::optional<std::string> CasePaths::referenceSolution(const CaseConfig& config) const {
  if (!config.reference_solution) return std::nullopt;
  return (fs::path(dir_) / *config.reference_solution).string();
}
std::string CasePaths::labStatic() const {
  return (fs::path(dir_) / "lab" / "static.txt").string();
}
std::string CasePaths::sixPosition(int axis, bool up) const {
  if (axis < 0 || axis > 2)
    throw std::invalid_argument("CasePaths::sixPosition: axis must be 0, 1 or 2, got " +
                                std::to_string(axis));
  const std::string name = std::string(1, "xyz"[axis]) + (up ? "_up.txt" : "_down.txt");
  return (fs::path(dir_) / "lab" / "six_position" / name).string();
}
std::string CasePaths::rateDir() const { return (fs::path(dir_) / "lab" / "rate").string(); }
std::string CasePaths::tilt(const std::string& name) const {
  return (fs::path(dir_) / "lab" / "tilt" / (name + ".txt")).string();
}
bool CasePaths::exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

std::optional<RateFile> parseRateFileName(const std::string& file_name) {
  // <x|y|z>_<pos|neg>_<number>.txt
  if (file_name.size() < 11 || file_name.compare(file_name.size() - 4, 4, ".txt") != 0)
    return std::nullopt;
  const char a = file_name[0];
  if ((a != 'x' && a != 'y' && a != 'z') || file_name[1] != '_') return std::nullopt;
  const std::string sign = file_name.substr(2, 4);
  if (sign != "pos_" && sign != "neg_") return std::nullopt;
  const char* b = file_name.data() + 6;
  const char* e = file_name.data() + file_name.size() - 4;
  double rate = 0.0;
  const auto res = std::from_chars(b, e, rate);
  if (res.ec != std::errc() || res.ptr != e || !(rate > 0.0) || !std::isfinite(rate))
    return std::nullopt;
  RateFile r;
  r.axis = a - 'x';
  r.sign = sign == "pos_" ? 1 : -1;
  r.rate_deg_s = rate;
  return r;
}

std::vector<RateFile> CasePaths::rateFiles() const {
  std::vector<RateFile> out;
  std::error_code ec;
  if (!fs::is_directory(rateDir(), ec)) return out;
  for (const auto& entry : fs::directory_iterator(rateDir())) {
    if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
    auto r = parseRateFileName(entry.path().filename().string());
    if (!r)
      throw std::runtime_error(
          entry.path().string() +
          ": rate file name does not follow <x|y|z>_<pos|neg>_<deg/s>.txt (e.g. z_neg_30.txt)");
    r->path = entry.path().string();
    out.push_back(*r);
  }
  std::sort(out.begin(), out.end(), [](const RateFile& l, const RateFile& r) {
    if (l.axis != r.axis) return l.axis < r.axis;
    if (l.sign != r.sign) return l.sign < r.sign;
    return l.rate_deg_s < r.rate_deg_s;
  });
  return out;
}

}  // namespace graftnav
