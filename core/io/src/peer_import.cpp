#include "graftnav/io/peer_import.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "graftnav/io/atomic_file.h"
#include "graftnav/io/case_config.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

// Whitespace-separated columns of the first line that is not empty or a '#'/'%' comment.
int firstLineColumns(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  while (std::getline(in, line)) {
    const auto p = line.find_first_not_of(" \t\r");
    if (p == std::string::npos || line[p] == '#' || line[p] == '%') continue;
    std::istringstream ss(line);
    int n = 0;
    for (std::string tok; ss >> tok;) ++n;
    return n;
  }
  throw std::runtime_error(path + ": no data line");
}

// The first `columns` columns of every line of `from`, written atomically to `to`.
void copyColumns(const std::string& from, const std::string& to, int columns) {
  std::ifstream in(from);
  if (!in) throw std::runtime_error(from + ": cannot open");
  std::string out, line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string tok;
    for (int i = 0; i < columns && ss >> tok; ++i) out += (i ? " " : "") + tok;
    out += '\n';
  }
  writeFileAtomically(to, out);
}

// Places `source` at `dest`: a symbolic link (absolute target), a copy, or a copy of the first
// `columns` columns when the file has more. Returns a note when the file was changed.
std::string placeDataFile(const std::string& source, const std::string& dest, int columns,
                          bool copy) {
  fs::remove(dest);
  const int have = firstLineColumns(source);
  if (have > columns) {
    copyColumns(source, dest, columns);
    return fmt::format("{}: {} columns; copied with the first {} into {}", source, have, columns,
                       dest);
  }
  if (copy) {
    fs::copy_file(source, dest, fs::copy_options::overwrite_existing);
  } else {
    fs::create_symlink(fs::absolute(source), dest);
  }
  return {};
}

// OB_GINS's odometer columns (8, or the mean of 8 and 9) of the IMU file as field/odometer.txt,
// each speed stamped at the middle of its sample (it is the mean speed over the interval that
// ends at the line's time). Throws std::runtime_error naming file and line for a line without
// them or a non-number.
void writeOdometerColumns(const std::string& imu_path, const std::string& dest, int columns,
                          double rate_hz) {
  std::ifstream in(imu_path);
  if (!in) throw std::runtime_error(imu_path + ": cannot open");
  OdometerSeries out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto p = line.find_first_not_of(" \t\r");
    if (p == std::string::npos || line[p] == '#' || line[p] == '%') continue;
    std::istringstream ss(line);
    std::vector<double> v;
    for (double x; ss >> x;) v.push_back(x);
    if (!ss.eof() || static_cast<int>(v.size()) < 7 + columns) {
      throw std::runtime_error(
          fmt::format("{}:{}: expected {} numeric columns (imudatalen), got "
                      "'{}'",
                      imu_path, n, 7 + columns, line));
    }
    const double speed = columns == 2 ? 0.5 * (v[7] + v[8]) : v[7];
    out.push_back({v[0] - 0.5 / rate_hz, speed});
  }
  writeOdometer(dest, out);
}

double medianInterval(const GnssSeries& gnss) {
  std::vector<double> dt;
  for (size_t i = 1; i < gnss.size(); ++i) dt.push_back(gnss[i].t_s - gnss[i - 1].t_s);
  if (dt.empty()) return 0.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

std::vector<TimeWindow> scheduleWindows(const PeerOutageSchedule& o, double t_end_s) {
  std::vector<TimeWindow> w;
  for (double t = o.first_start_s; t + o.length_s <= t_end_s; t += o.period_s)
    w.push_back({t, t + o.length_s});
  return w;
}

NavState initialState(const PeerSetup& s, const GnssSeries& gnss, std::vector<std::string>* notes) {
  NavState x;
  x.t_s = s.start_s;
  x.v_n = s.initial_velocity_ned_m_s;
  x.q_nb = quatFromEuler(s.initial_euler_rad);
  if (s.initial_position) {
    x.pos = *s.initial_position;
    return x;
  }
  const auto it = std::find_if(gnss.begin(), gnss.end(),
                               [&](const GnssFix& f) { return f.t_s >= s.start_s - 1e-6; });
  if (it == gnss.end())
    throw std::runtime_error(s.gnss_path + ": no GNSS fix at or after starttime " +
                             fmt::format("{}", s.start_s));
  const Eigen::Vector3d lever_n = x.q_nb * s.lever_arm_m.value_or(Eigen::Vector3d::Zero());
  x.pos = earth::offsetByNed(it->pos, -lever_n);
  notes->push_back(fmt::format(
      "initial position: GNSS fix at t={:.3f} ({:.3f} s after starttime), std N/E/U "
      "{:.3f}/{:.3f}/{:.3f} m",
      it->t_s, it->t_s - s.start_s, it->std_ned_m.x(), it->std_ned_m.y(), it->std_ned_m.z()));
  return x;
}

CaseConfig caseConfig(const PeerSetup& s, const NavState& initial, const ImportOptions& o) {
  CaseConfig c;
  c.name = o.case_name.empty() ? fs::path(s.config_path).stem().string() : o.case_name;
  c.imu_rate_hz = s.imu_rate_hz;
  c.reference_imu = s.profile;
  c.reference_imu_noise_given = true;
  c.lever_arm_m = s.lever_arm_m;
  c.initial_state = initial;
  if (!o.reference_path.empty()) c.reference_solution = "field/reference.nav";
  return c;
}

void emitScalar(YAML::Emitter& out, const char* key, double value) {
  out << YAML::Key << key << YAML::Value << value;
}

std::string runConfigYaml(const PeerSetup& s, const std::vector<TimeWindow>& outages) {
  YAML::Emitter out;
  out.SetDoublePrecision(15);
  out << YAML::BeginMap;
  out << YAML::Key << "time_range" << YAML::Value << YAML::BeginMap;
  emitScalar(out, "start_s", s.start_s);
  if (s.end_s) emitScalar(out, "end_s", *s.end_s);
  out << YAML::EndMap;
  if (!outages.empty()) {
    out << YAML::Key << "outages" << YAML::Value << YAML::BeginMap << YAML::Key << "windows"
        << YAML::Value << YAML::BeginSeq;
    for (const auto& w : outages)
      out << YAML::Flow << YAML::BeginSeq << w.start_s << w.end_s << YAML::EndSeq;
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::Key << "ekf" << YAML::Value << YAML::BeginMap;
  if (s.initial_pos_std_m) emitScalar(out, "init_pos_std_m", s.initial_pos_std_m->maxCoeff());
  if (s.initial_vel_std_m_s) emitScalar(out, "init_vel_std_m_s", s.initial_vel_std_m_s->maxCoeff());
  if (s.initial_att_std_rad) {
    emitScalar(out, "init_roll_pitch_std_deg",
               s.initial_att_std_rad->head<2>().maxCoeff() * units::kRadToDeg);
    emitScalar(out, "init_heading_std_deg", s.initial_att_std_rad->z() * units::kRadToDeg);
  }
  emitScalar(out, "gate_probability", 0.0);
  out << YAML::EndMap;
  if (s.gnss_max_std_m) {
    out << YAML::Key << "gnss" << YAML::Value << YAML::BeginMap;
    emitScalar(out, "max_horizontal_std_m", *s.gnss_max_std_m);
    emitScalar(out, "max_vertical_std_m", *s.gnss_max_std_m);
    out << YAML::EndMap;
  }
  if (s.odometer) {
    const PeerOdometer& o = *s.odometer;
    out << YAML::Key << "odometer" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "enabled" << YAML::Value << o.enabled;
    out << YAML::Key << "std_m_s" << YAML::Value << YAML::Flow << YAML::BeginSeq << o.std_m_s.x()
        << o.std_m_s.y() << o.std_m_s.z() << YAML::EndSeq;
    emitScalar(out, "rate_hz", o.rate_hz);
    if (o.scale_random_walk_per_sqrt_s) {
      emitScalar(out, "scale_random_walk_ppm_sqrt_s",
                 *o.scale_random_walk_per_sqrt_s / units::kPpmToFraction);
    }
    out << YAML::Key << "lever_arm_m" << YAML::Value << YAML::Flow << YAML::BeginSeq
        << o.lever_arm_m.x() << o.lever_arm_m.y() << o.lever_arm_m.z() << YAML::EndSeq;
    const Eigen::Vector3d deg = o.mounting_rad * units::kRadToDeg;
    out << YAML::Key << "mounting_deg" << YAML::Value << YAML::Flow << YAML::BeginSeq << deg.x()
        << deg.y() << deg.z() << YAML::EndSeq;
    out << YAML::EndMap;
  }
  if (s.window_nodes || s.earth_rotation) {
    out << YAML::Key << "fgo" << YAML::Value << YAML::BeginMap;
    if (s.window_nodes) out << YAML::Key << "window_nodes" << YAML::Value << *s.window_nodes;
    if (s.earth_rotation) out << YAML::Key << "earth_rotation" << YAML::Value << *s.earth_rotation;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return "# Run config written by `graftnav import " + peerFormatName(s.format) + "` from " +
         s.config_path +
         "\n# (every key: configs/navigate.yaml; see notes.md for what was converted)\n" +
         out.c_str() + "\n";
}

std::string notesMarkdown(const PeerSetup& s, const ImportResult& r) {
  std::string md = "# Imported from " + peerFormatName(s.format) + "\n\nSource: `" + s.config_path +
                   "`\n\nIMU file: `" + s.imu_path + "`\n\nGNSS file: `" + s.gnss_path + "`\n\n";
  md += fmt::format("Outage windows ({}):\n\n", r.outages.size());
  for (const auto& w : r.outages)
    md += fmt::format("- {:.3f} .. {:.3f} ({:.1f} s)\n", w.start_s, w.end_s, w.length_s());
  md += "\nWhat the import assumed or could not convert:\n\n";
  for (const auto& n : r.notes) md += "- " + n + "\n";
  return md;
}

}  // namespace

void ImportOptions::validate() const {
  if (!(min_gap_s > 0.0))
    throw std::invalid_argument(fmt::format("ImportOptions.min_gap_s {} must be > 0", min_gap_s));
  if (!(gap_factor >= 1.0))
    throw std::invalid_argument(
        fmt::format("ImportOptions.gap_factor {} must be >= 1", gap_factor));
}

std::vector<TimeWindow> gnssGapWindows(const GnssSeries& gnss, double t_begin_s, double t_end_s,
                                       const ImportOptions& options) {
  options.validate();
  const double threshold = std::max(options.min_gap_s, options.gap_factor * medianInterval(gnss));
  constexpr double kEdge =
      1e-3;  // keeps both bounding fixes outside the window (TimeWindow is closed)
  std::vector<TimeWindow> w;
  for (size_t i = 1; i < gnss.size(); ++i) {
    const double a = gnss[i - 1].t_s, b = gnss[i].t_s;
    if (b - a > threshold && a >= t_begin_s && b <= t_end_s) w.push_back({a + kEdge, b - kEdge});
  }
  return w;
}

ImportResult importPeerSetup(const PeerSetup& s, const std::string& case_dir,
                             const ImportOptions& o) {
  o.validate();
  ImportResult r;
  r.case_dir = case_dir;
  r.notes = s.notes;
  const fs::path dir(case_dir);
  fs::create_directories(dir / "field");
  fs::create_directories(dir / "source");
  GnssReadPolicy policy = GnssReadPolicy::real();
  const std::string gnss_dest = (dir / "field" / "gnss.pos").string();
  if (const auto n = placeDataFile(s.gnss_path, gnss_dest, 7, o.copy_files); !n.empty())
    r.notes.push_back(n);
  const GnssSeries gnss = readGnssPos(gnss_dest, policy);
  if (const auto n =
          placeDataFile(s.imu_path, (dir / "field" / "ref_imu.txt").string(), 7, o.copy_files);
      !n.empty())
    r.notes.push_back(n);
  const std::string odometer_dest = (dir / "field" / "odometer.txt").string();
  fs::remove(odometer_dest);
  if (s.odometer_columns > 0)
    writeOdometerColumns(s.imu_path, odometer_dest, s.odometer_columns, s.imu_rate_hz);
  if (!o.reference_path.empty()) {
    if (!fs::is_regular_file(o.reference_path))
      throw std::runtime_error("reference solution '" + o.reference_path + "' not found");
    placeDataFile(o.reference_path, (dir / "field" / "reference.nav").string(), 11, o.copy_files);
  } else {
    r.notes.push_back(
        "no reference solution given (--reference FILE.nav): navigate writes no errors");
  }
  const NavState initial = initialState(s, gnss, &r.notes);
  const double t_end = s.end_s.value_or(gnss.back().t_s);
  if (s.outage_schedule) {
    r.outages = scheduleWindows(*s.outage_schedule, t_end);
  } else {
    r.outages = gnssGapWindows(gnss, s.start_s, t_end, o);
    r.notes.push_back(
        fmt::format("{} outage windows from GNSS gaps longer than max({} s, {} x the median "
                    "interval {:.3f} s)",
                    r.outages.size(), o.min_gap_s, o.gap_factor, medianInterval(gnss)));
  }
  r.notes.push_back("the peer's EKF has no innovation gate: ekf.gate_probability 0 (off)");
  saveCaseConfig((dir / "case.yaml").string(), caseConfig(s, initial, o));
  writeFileAtomically((dir / "run.yaml").string(), runConfigYaml(s, r.outages));
  fs::copy_file(s.config_path, dir / "source" / fs::path(s.config_path).filename(),
                fs::copy_options::overwrite_existing);
  writeFileAtomically((dir / "notes.md").string(), notesMarkdown(s, r));
  return r;
}

}  // namespace graftnav
