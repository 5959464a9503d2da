#include "sg_report.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav::app {
namespace {

// Statistic i of a DriftStats array in report units (m or deg).
double reportValue(const std::array<double, 5>& a, int i) {
  return i < 2 ? a[i] : a[i] * units::kRadToDeg;
}

nlohmann::json statsJson(const DriftStats& s, bool fraction) {
  nlohmann::json j = nlohmann::json::object();
  const auto a = asArray(s);
  for (int i = 0; i < 5; ++i) {
    const double v = fraction ? a[i] : reportValue(a, i);
    j[driftStatNames()[i]] = std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  }
  return j;
}

std::string pct(double f) { return std::isfinite(f) ? fmt::format("{:.2f}%", 100.0 * f) : "n/a"; }
std::string num(double v, int digits) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "n/a";
}

// The seed's published tables (Niu et al. 2016, Tables 2 and 3), for side-by-side reading.
struct SeedRow {
  const char* label;
  std::array<double, 5> v;
};
const std::vector<SeedRow>& seedTable(const std::string& grade) {
  static const std::vector<SeedRow> tactical{
      {"ERR_1", {3.758, 0.518, 0.027, 0.022, 0.066}},   {"ERR_2", {4.857, 0.651, 0.029, 0.025, 0.093}},
      {"ERR_REAL", {4.688, 0.651, 0.029, 0.024, 0.097}}, {"DIFF_1", {19.84, 20.43, 6.90, 8.33, 31.96}},
      {"DIFF_2", {3.60, 0.00, 0.00, 4.17, 4.12}}};
  static const std::vector<SeedRow> mems{
      {"ERR_1", {12.983, 3.131, 0.077, 0.063, 0.334}},   {"ERR_2", {20.422, 7.842, 0.113, 0.117, 0.378}},
      {"ERR_REAL", {17.657, 6.566, 0.100, 0.098, 0.516}}, {"DIFF_1", {26.47, 52.31, 23.00, 35.71, 35.27}},
      {"DIFF_2", {15.66, 19.43, 13.00, 19.39, 26.74}}};
  static const std::vector<SeedRow> none;
  if (grade == "tactical") return tactical;
  if (grade == "mems") return mems;
  return none;
}

}  // namespace

const SgSolutionErrors* SgEvaluationReport::find(const std::string& label) const {
  for (const auto& s : solutions)
    if (s.label == label) return &s;
  return nullptr;
}

std::optional<DriftStats> SgEvaluationReport::diff(const std::string& label) const {
  const auto* x = find(label);
  const auto* real = find("REAL");
  if (!x || !real) return std::nullopt;
  return relativeDifference(x->evaluation.outage_rms, real->evaluation.outage_rms);
}

std::string driftStatsJson(const DriftStats& s, int indent) { return statsJson(s, false).dump(indent); }

void writeEvaluationJson(const std::string& path, const SgEvaluationReport& r) {
  nlohmann::json j;
  j["case"] = r.case_name;
  j["estimator"] = r.estimator;
  j["outages"] = {{"count", static_cast<int>(r.outages.size())}, {"length_s", r.outage_length_s}};
  nlohmann::json err = nlohmann::json::object(), err_max = nlohmann::json::object(),
                 diff = nlohmann::json::object();
  for (const auto& s : r.solutions) {
    err[s.label] = statsJson(s.evaluation.outage_rms, false);
    err_max[s.label] = statsJson(s.evaluation.outage_max_rms, false);
  }
  j["err"] = err;
  if (r.find("REAL")) {
    for (const auto& s : r.solutions)
      if (s.label != "REAL") diff[s.label] = statsJson(*r.diff(s.label), true);
    j["diff"] = diff;
  }
  // Extra keys (allowed by the contract).
  j["err_outage_max"] = err_max;
  j["reference"] = r.reference;
  nlohmann::json wins = nlohmann::json::array();
  for (const auto& w : r.outages) wins.push_back({w.start_s, w.end_s});
  j["outage_windows_s"] = wins;
  j["notes"] = r.notes;
  writeFileAtomically(path, j.dump(2) + "\n");
}

void writeTablesMarkdown(const std::string& path, const SgEvaluationReport& r) {
  std::string md;
  md += fmt::format("# Signal-grafting evaluation: {}\n\n", r.case_name);
  md += fmt::format("Estimator `{}`; {} GNSS outages of {:.0f} s; SOL_REF: {}.\n\n", r.estimator,
                    r.outages.size(), r.outage_length_s, r.reference);
  md += "Statistics are the seed's: RMS over all epochs inside the outages of the error against "
        "SOL_REF (Horizontal = sqrt(dN^2 + dE^2), Vertical = |dD|); DIFF_x = |ERR_x - ERR_REAL| / "
        "ERR_REAL.\n\n";
  auto table = [&](const std::string& title, bool max_stat) {
    md += "## " + title + "\n\n";
    md += "| | Horizontal (m) | Vertical (m) | Roll (deg) | Pitch (deg) | Heading (deg) |\n";
    md += "|---|---|---|---|---|---|\n";
    for (const auto& s : r.solutions) {
      const std::string name = s.label == "REAL" ? "ERR_REAL" : "ERR_" + s.label.substr(2);
      const auto a = asArray(max_stat ? s.evaluation.outage_max_rms : s.evaluation.outage_rms);
      md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", name, num(reportValue(a, 0), 3),
                        num(reportValue(a, 1), 3), num(reportValue(a, 2), 3), num(reportValue(a, 3), 3),
                        num(reportValue(a, 4), 3));
    }
    if (!max_stat && r.find("REAL")) {
      for (const auto& s : r.solutions) {
        if (s.label == "REAL") continue;
        const auto d = asArray(*r.diff(s.label));
        md += fmt::format("| DIFF_{} | {} | {} | {} | {} | {} |\n", s.label.substr(2), pct(d[0]),
                          pct(d[1]), pct(d[2]), pct(d[3]), pct(d[4]));
      }
    }
    md += "\n";
  };
  table("Outage errors (seed Table 2/3 layout)", false);
  table("RMS of per-outage maximum drift (the peers' statistic)", true);
  const auto& seed = seedTable(r.tested_grade);
  if (!seed.empty()) {
    md += fmt::format("## The seed's published table for a {} IMU (Niu et al. 2016)\n\n",
                      r.tested_grade == "mems" ? "MEMS (POS1100, Table 3)" : "tactical (POS310, Table 2)");
    md += "Different field test and IMU units: read for shape (DIFF_2 vs DIFF_1), not for equality.\n\n";
    md += "| | Horizontal | Vertical | Roll | Pitch | Heading |\n|---|---|---|---|---|---|\n";
    for (const auto& row : seed) {
      const bool is_pct = std::string(row.label).rfind("DIFF", 0) == 0;
      md += fmt::format("| {} |", row.label);
      for (double v : row.v) md += is_pct ? fmt::format(" {:.2f}% |", v) : fmt::format(" {:.3f} |", v);
      md += "\n";
    }
    md += "\n";
  }
  if (!r.notes.empty()) {
    md += "## Notes\n\n";
    for (const auto& n : r.notes) md += "- " + n + "\n";
  }
  writeFileAtomically(path, md);
}

void writeEvaluationCsv(const std::string& path, const SgEvaluationReport& r) {
  std::string csv = "row,statistic,horizontal_m,vertical_m,roll_deg,pitch_deg,heading_deg\n";
  for (const auto& s : r.solutions) {
    for (int k = 0; k < 2; ++k) {
      const auto a = asArray(k == 0 ? s.evaluation.outage_rms : s.evaluation.outage_max_rms);
      csv += fmt::format("ERR_{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.label,
                         k == 0 ? "rms_over_outage_epochs" : "rms_of_outage_maxima", reportValue(a, 0),
                         reportValue(a, 1), reportValue(a, 2), reportValue(a, 3), reportValue(a, 4));
    }
  }
  for (const auto& s : r.solutions) {
    if (s.label == "REAL" || !r.find("REAL")) continue;
    const auto d = asArray(*r.diff(s.label));
    csv += fmt::format("DIFF_{},fraction,{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.label, d[0], d[1], d[2],
                       d[3], d[4]);
  }
  writeFileAtomically(path, csv);
}

void writePerOutageCsv(const std::string& path, const SgEvaluationReport& r) {
  std::string csv =
      "solution,outage,start_s,end_s,epochs,max_horizontal_m,max_vertical_m,max_roll_deg,max_pitch_deg,"
      "max_heading_deg\n";
  for (const auto& s : r.solutions) {
    int i = 0;
    for (const auto& o : s.evaluation.outages) {
      const auto a = asArray(o.max);
      csv += fmt::format("{},{},{:.3f},{:.3f},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.label, i++,
                         o.window.start_s, o.window.end_s, o.epochs, reportValue(a, 0), reportValue(a, 1),
                         reportValue(a, 2), reportValue(a, 3), reportValue(a, 4));
    }
  }
  writeFileAtomically(path, csv);
}

}  // namespace graftnav::app
