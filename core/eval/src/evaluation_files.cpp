#include "graftnav/eval/evaluation_files.h"

#include <fmt/core.h>
#include <fmt/os.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "graftnav/eval/errors_csv.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"
#include "graftnav/io/provenance.h"

namespace graftnav {
namespace {

using nlohmann::json;

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json drift(const DriftStats& s) {
  return {{"horizontal_m", num(s.horizontal_m)},
          {"vertical_m", num(s.vertical_m)},
          {"roll_deg", num(s.roll_rad * units::kRadToDeg)},
          {"pitch_deg", num(s.pitch_rad * units::kRadToDeg)},
          {"heading_deg", num(s.heading_rad * units::kRadToDeg)}};
}

void writeText(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text);
}

}  // namespace

std::string missingStatisticsReason(const Evaluation& ev) {
  std::vector<std::string> why;
  if (ev.epoch_count == 0) why.push_back("no solution epoch inside the reference span");
  if (ev.outages.empty())
    why.push_back("no outage statistics: no outage window with a reference epoch");
  else if (ev.outage_epochs == 0)
    why.push_back("no outage statistics: no reference epoch inside the outages");
  if (ev.nees_samples == 0)
    why.push_back("no NEES: no epoch with a solution sigma and a reference");
  std::string s;
  for (const auto& w : why) s += (s.empty() ? "" : "; ") + w;
  return s;
}

nlohmann::json errorsJson(const ReportMeta& m, const Evaluation& ev) {
  json j;
  j["estimator"] = m.estimator;
  j["imu"] = m.imu;
  j["outages"] = {{"count", m.outage_count}, {"length_s", num(m.outage_length_s)}};
  const DriftStats& o = ev.overall_rms;
  j["overall"] = {{"horizontal_rms_m", num(o.horizontal_m)},
                  {"vertical_rms_m", num(o.vertical_m)},
                  {"roll_rms_deg", num(o.roll_rad * units::kRadToDeg)},
                  {"pitch_rms_deg", num(o.pitch_rad * units::kRadToDeg)},
                  {"heading_rms_deg", num(o.heading_rad * units::kRadToDeg)}};
  j["outage"] = drift(ev.outage_rms);
  j["outage_max"] = drift(ev.outage_max_rms);
  j["nees"] = num(ev.nees_mean);
  return j;
}

std::vector<std::string> writeErrorsJson(const std::string& path, const ReportMeta& m,
                                         const Evaluation& ev) {
  return writeJsonResult(path, errorsJson(m, ev), missingStatisticsReason(ev));
}

std::vector<std::string> writeRunInfoJson(const std::string& path, const ReportMeta& m,
                                          const Evaluation& ev, const NavSolution& sol,
                                          const std::vector<TimeWindow>& outages,
                                          const std::vector<std::string>& notes,
                                          double run_time_s) {
  json j;
  j["estimator"] = m.estimator;
  j["imu"] = m.imu;
  j["nees"] = {{"mean", num(ev.nees_mean)},
               {"dof", ev.nees_dof},
               {"samples", ev.nees_samples},
               {"band_95", {num(ev.nees_band_low), num(ev.nees_band_high)}},
               {"note",
                "9 PVA states, diagonal sigma; samples taken every nees_interval_s are "
                "correlated in time, so the band is optimistic"}};
  j["gnss"] = {
      {"used", sol.gnss_used}, {"rejected", sol.gnss_rejected}, {"withheld", sol.gnss_withheld}};
  if (sol.vehicle_used > 0 || sol.vehicle_rejected > 0 || !sol.odometer_scale.empty()) {
    // Odometer / NHC updates (factors in a graph) and the last odometer scale estimate (ppm).
    json v = {{"used", sol.vehicle_used}, {"rejected", sol.vehicle_rejected}};
    if (!sol.odometer_scale.empty()) {
      v["odometer_scale_ppm"] = num(sol.odometer_scale.back() * 1e6);
      v["odometer_scale_std_ppm"] = num(sol.odometer_scale_std.back() * 1e6);
    }
    j["vehicle_aiding"] = v;
  }
  json w = json::array();
  for (const TimeWindow& t : outages) w.push_back({t.start_s, t.end_s});
  j["outage_windows_s"] = w;
  j["epochs_evaluated"] = ev.epoch_count;
  j["outage_epochs"] = ev.outage_epochs;
  j["run_time_s"] = num(run_time_s);
  j["notes"] = notes;
  j["provenance"] = provenanceJson();
  return writeJsonResult(path, j, missingStatisticsReason(ev));
}

void writeErrorsCsv(const std::string& path, const Evaluation& ev, double min_interval_s) {
  ErrorsCsvWriter w(path, min_interval_s);
  for (const EpochError& e : ev.epochs) w.add(e);
  w.commit();
}

void writeOutageCsv(const std::string& path, const Evaluation& ev) {
  std::string out =
      "index,start_s,end_s,epochs,max_horizontal_m,max_vertical_m,max_roll_deg,max_pitch_deg,"
      "max_heading_deg\n";
  const double r2d = units::kRadToDeg;
  for (size_t i = 0; i < ev.outages.size(); ++i) {
    const OutageDrift& d = ev.outages[i];
    if (!std::isfinite(d.max.horizontal_m) || !std::isfinite(d.max.vertical_m) ||
        !std::isfinite(d.max.roll_rad) || !std::isfinite(d.max.pitch_rad) ||
        !std::isfinite(d.max.heading_rad))
      throw std::runtime_error(fmt::format(
          "{}: the maxima of outage {} are not finite; refusing to write them", path, i));
    out +=
        fmt::format("{},{:.3f},{:.3f},{},{:.4f},{:.4f},{:.6f},{:.6f},{:.6f}\n", i, d.window.start_s,
                    d.window.end_s, d.epochs, d.max.horizontal_m, d.max.vertical_m,
                    d.max.roll_rad * r2d, d.max.pitch_rad * r2d, d.max.heading_rad * r2d);
  }
  writeText(path, out);
}

}  // namespace graftnav
