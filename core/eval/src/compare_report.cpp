#include "graftnav/eval/compare_report.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "graftnav/io/atomic_file.h"
#include "graftnav/io/provenance.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

// A number as JSON, null when it is not finite.
nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

// One drift statistic as JSON (degrees for angles).
nlohmann::json driftJson(const DriftStats& d) {
  return {{"horizontal_m", num(d.horizontal_m)},
          {"vertical_m", num(d.vertical_m)},
          {"roll_deg", num(d.roll_rad * units::kRadToDeg)},
          {"pitch_deg", num(d.pitch_rad * units::kRadToDeg)},
          {"heading_deg", num(d.heading_rad * units::kRadToDeg)}};
}

// Formats table cells; a statistic that cannot be computed is written as absent and counted.
struct Cells {
  int absent = 0;
  std::string operator()(double v, const char* f, const char* absent_text) {
    if (std::isfinite(v)) return fmt::format(fmt::runtime(f), v);
    ++absent;
    return absent_text;
  }
  // The five statistics (position in m, attitude in deg) joined by `sep`.
  std::string drift(const DriftStats& d, const char* sep, const char* position_format,
                    const char* attitude_format, const char* absent_text) {
    const double values[5] = {d.horizontal_m, d.vertical_m, d.roll_rad * units::kRadToDeg,
                              d.pitch_rad * units::kRadToDeg, d.heading_rad * units::kRadToDeg};
    std::string row;
    for (int i = 0; i < 5; ++i) {
      if (i > 0) row += sep;
      row += (*this)(values[i], i < 2 ? position_format : attitude_format, absent_text);
    }
    return row;
  }
  std::string driftMd(const DriftStats& d) { return drift(d, " | ", "{:.3f}", "{:.4f}", "-"); }
  std::string driftCsv(const DriftStats& d) { return drift(d, ",", "{:.6f}", "{:.6f}", ""); }
};

// One statistic of the cross-check; `scale` turns the difference's unit into the key's.
nlohmann::json crossCheckStatJson(const CrossCheckStat& s, double scale) {
  return {{"rms_sigma", num(s.rms_sigma * scale)},
          {"rms_normalized", num(s.rms_normalized)},
          {"max_normalized", num(s.max_normalized)},
          {"max_normalized_t_s", num(s.max_normalized_t_s)},
          {"epochs", s.normalized_epochs}};
}

// "sigma": the form of the difference's variance, or "none" when a solution has no sigmas.
nlohmann::json crossCheckJson(const CrossCheck& c) {
  if (!c.has_sigma) return {{"sigma", "none"}};
  return {{"sigma", differenceCovarianceName(c.form)},
          {"horizontal_m", crossCheckStatJson(c.horizontal, 1.0)},
          {"vertical_m", crossCheckStatJson(c.vertical, 1.0)},
          {"heading_deg", crossCheckStatJson(c.heading, units::kRadToDeg)}};
}

void ratiosMd(const std::vector<CompareRow>& rows, Cells& cell, std::ostringstream& md) {
  md << fmt::format(
      "\n## Ratios to {} (outage RMS)\n\n| estimator | horiz. | vert. | heading |\n"
      "|---|---|---|---|\n",
      rows.front().name);
  const DriftStats& b = rows.front().eval.outage_rms;
  for (const CompareRow& r : rows) {
    const DriftStats& d = r.eval.outage_rms;
    md << fmt::format("| {} | {} | {} | {} |\n", r.name,
                      cell(d.horizontal_m / b.horizontal_m, "{:.3f}", "-"),
                      cell(d.vertical_m / b.vertical_m, "{:.3f}", "-"),
                      cell(d.heading_rad / b.heading_rad, "{:.3f}", "-"));
  }
}

std::string compareMarkdown(const CompareReport& r, Cells& cell) {
  std::ostringstream md;
  md << fmt::format(
      "# Estimator comparison: {}\n\nIMU: {} ({}), {} outages of {:.0f} s every "
      "{:.0f} s from {:.0f} s; errors against the {}.\n\n",
      r.case_dir, r.imu, r.imu_profile_name, r.outages.size(), r.schedule.length_s,
      r.schedule.period_s, r.schedule.start_s, r.reference_name);
  md << "## Outage errors, RMS over outage epochs (seed Tables 2-3)\n\n"
        "| estimator | horiz. (m) | vert. (m) | roll (deg) | pitch (deg) | heading (deg) | "
        "run (s) | GNSS rejected |\n|---|---|---|---|---|---|---|---|\n";
  for (const CompareRow& row : r.rows) {
    md << fmt::format("| {} | {} | {:.2f} | {} |\n", row.name, cell.driftMd(row.eval.outage_rms),
                      row.seconds, row.gnss_rejected);
  }
  md << "\n## Outage errors, RMS over outages of the per-outage maximum (peers)\n\n"
        "| estimator | horiz. (m) | vert. (m) | roll (deg) | pitch (deg) | heading (deg) |\n"
        "|---|---|---|---|---|---|\n";
  for (const CompareRow& row : r.rows)
    md << fmt::format("| {} | {} |\n", row.name, cell.driftMd(row.eval.outage_max_rms));
  if (!r.rows.empty()) ratiosMd(r.rows, cell, md);
  md << "\n## Differences between estimators inside outages (RMS over outage epochs)\n\n"
        "| a - b | horiz. (m) | vert. (m) | roll (deg) | pitch (deg) | heading (deg) |\n"
        "|---|---|---|---|---|---|\n";
  for (const ComparePair& q : r.pairs)
    md << fmt::format("| {} - {} | {} |\n", q.a, q.b, cell.driftMd(q.rms));
  return md.str();
}

// CSV: one row per estimator and statistic, and per pair.
std::string compareCsv(const CompareReport& r, Cells& cell) {
  std::ostringstream csv;
  csv << "kind,name,statistic,horizontal_m,vertical_m,roll_deg,pitch_deg,heading_deg,run_s,"
         "gnss_rejected\n";
  for (const CompareRow& row : r.rows) {
    csv << fmt::format("error,{},outage_rms,{},{:.3f},{}\n", row.name,
                       cell.driftCsv(row.eval.outage_rms), row.seconds, row.gnss_rejected);
    csv << fmt::format("error,{},outage_max_rms,{},{:.3f},{}\n", row.name,
                       cell.driftCsv(row.eval.outage_max_rms), row.seconds, row.gnss_rejected);
    csv << fmt::format("error,{},overall_rms,{},{:.3f},{}\n", row.name,
                       cell.driftCsv(row.eval.overall_rms), row.seconds, row.gnss_rejected);
  }
  for (const ComparePair& q : r.pairs) {
    csv << fmt::format("difference,{}-{},outage_rms,{},,\n", q.a, q.b, cell.driftCsv(q.rms));
    csv << fmt::format("difference,{}-{},outage_max_rms,{},,\n", q.a, q.b,
                       cell.driftCsv(q.max_rms));
  }
  return csv.str();
}

// The 1 Hz error series for the plot.
std::string errorSeriesCsv(const std::vector<CompareRow>& rows, Cells& cell) {
  std::ostringstream ser;
  ser << "t_s";
  for (const CompareRow& r : rows)
    ser << fmt::format(",{0}_horizontal_m,{0}_vertical_m,{0}_heading_deg", r.name);
  ser << "\n";
  const std::vector<EpochError>& first = rows.front().series;
  for (size_t k = 0; k < first.size(); ++k) {
    ser << fmt::format("{:.3f}", first[k].t_s);
    for (size_t r = 0; r < rows.size(); ++r) {
      const EpochError& e = rows[r].series.at(k);
      ser << fmt::format(",{},{},{}", cell(e.pos_ned_m.head<2>().norm(), "{:.4f}", ""),
                         cell(std::abs(e.pos_ned_m.z()), "{:.4f}", ""),
                         cell(e.euler_rad.z() * units::kRadToDeg, "{:.5f}", ""));
    }
    ser << "\n";
  }
  return ser.str();
}

// compare.json: the numbers of compare.csv, and the run's provenance.
nlohmann::json compareJson(const CompareReport& r) {
  nlohmann::json js = {{"case", r.case_dir},
                       {"imu", r.imu},
                       {"outage_count", r.outages.size()},
                       {"estimators", nlohmann::json::array()},
                       {"differences", nlohmann::json::array()},
                       {"provenance", provenanceJson()}};
  for (const CompareRow& row : r.rows) {
    js["estimators"].push_back({{"name", row.name},
                                {"run_s", row.seconds},
                                {"gnss_rejected", row.gnss_rejected},
                                {"outage_rms", driftJson(row.eval.outage_rms)},
                                {"outage_max_rms", driftJson(row.eval.outage_max_rms)},
                                {"overall_rms", driftJson(row.eval.overall_rms)}});
  }
  for (const ComparePair& q : r.pairs) {
    js["differences"].push_back({{"a", q.a},
                                 {"b", q.b},
                                 {"outage_rms", driftJson(q.rms)},
                                 {"outage_max_rms", driftJson(q.max_rms)},
                                 {"cross_check", crossCheckJson(q.cross)}});
  }
  return js;
}

}  // namespace

std::string writeCompareFiles(const CompareReport& r, const std::string& out_dir, int* absent) {
  Cells cell;
  const std::string md = compareMarkdown(r, cell);
  std::ostringstream ow;
  ow << "start_s,end_s\n";
  for (const TimeWindow& w : r.outages) ow << fmt::format("{:.3f},{:.3f}\n", w.start_s, w.end_s);
  writeFileAtomically(out_dir + "/compare.md", md);
  writeFileAtomically(out_dir + "/compare.csv", compareCsv(r, cell));
  writeFileAtomically(out_dir + "/compare_errors.csv", errorSeriesCsv(r.rows, cell));
  writeFileAtomically(out_dir + "/compare_outages.csv", ow.str());
  writeFileAtomically(out_dir + "/compare.json", compareJson(r).dump(2) + "\n");
  if (absent) *absent = cell.absent;
  return md;
}

void CompareSeriesSink::add(const EpochError& e) {
  last_ = e;
  if (!grid_) {
    if (kept_.empty() || e.t_s + 1e-9 >= next_t_) {
      next_t_ = e.t_s + 1.0;
      kept_.push_back(e);
    }
    return;
  }
  while (kept_.size() < grid_->size() && e.t_s >= (*grid_)[kept_.size()].t_s - 1e-9)
    kept_.push_back(e);
}

void CompareSeriesSink::commit() {
  if (grid_ && last_)
    while (kept_.size() < grid_->size()) kept_.push_back(*last_);
  *out_ = std::move(kept_);
}

}  // namespace graftnav
