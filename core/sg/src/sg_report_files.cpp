#include "graftnav/sg/sg_report_files.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include <filesystem>

#include "graftnav/eval/evaluation_files.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav {
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
const std::vector<SeedRow>& seedTable(std::optional<ImuGrade> grade) {
  static const std::vector<SeedRow> tactical{{"ERR_1", {3.758, 0.518, 0.027, 0.022, 0.066}},
                                             {"ERR_2", {4.857, 0.651, 0.029, 0.025, 0.093}},
                                             {"ERR_REAL", {4.688, 0.651, 0.029, 0.024, 0.097}},
                                             {"DIFF_1", {19.84, 20.43, 6.90, 8.33, 31.96}},
                                             {"DIFF_2", {3.60, 0.00, 0.00, 4.17, 4.12}}};
  static const std::vector<SeedRow> mems{{"ERR_1", {12.983, 3.131, 0.077, 0.063, 0.334}},
                                         {"ERR_2", {20.422, 7.842, 0.113, 0.117, 0.378}},
                                         {"ERR_REAL", {17.657, 6.566, 0.100, 0.098, 0.516}},
                                         {"DIFF_1", {26.47, 52.31, 23.00, 35.71, 35.27}},
                                         {"DIFF_2", {15.66, 19.43, 13.00, 19.39, 26.74}}};
  static const std::vector<SeedRow> none;
  if (grade == ImuGrade::kTactical) return tactical;
  if (grade == ImuGrade::kMems) return mems;
  return none;
}

// The SG strategies of a report that carry realizations.
std::vector<const SgSolutionErrors*> predictiveSolutions(const SgEvaluationReport& r) {
  std::vector<const SgSolutionErrors*> out;
  for (const auto& s : r.solutions)
    if (!s.draws.empty()) out.push_back(&s);
  return out;
}

const char* kStatHeader =
    "| | Horizontal (m) | Vertical (m) | Roll (deg) | Pitch (deg) | Heading (deg) |\n|---|---|---|---|---|---|\n";

std::string rowName(const SgSolutionErrors& s) {
  return s.label == "REAL" ? "ERR_REAL" : "ERR_" + s.label.substr(2);
}

// Means only (ERR and DIFF), one row per solution.
std::string meanTable(const SgEvaluationReport& r, bool max_stat) {
  std::string md = kStatHeader;
  for (const auto& s : r.solutions) {
    const auto a = asArray(max_stat ? s.err_max_rms : s.err_rms);
    md += fmt::format("| {} |", rowName(s));
    for (int i = 0; i < 5; ++i) md += " " + num(reportValue(a, i), 3) + " |";
    md += "\n";
  }
  return md + "\n";
}

std::string predictiveIntro(const SgEvaluationReport& r) {
  return fmt::format(
      "ERR_1 and ERR_2 are means over {} grafted realizations{}; brackets hold the 90 % predictive "
      "interval [p05, p95] of one realization, where ERR_REAL should fall if grafting lacks no "
      "physics. DIFF_x is computed from the mean; its brackets hold the 90 % interval of a "
      "single realization's DIFF. \"REAL in SG#x\" is the fraction of realizations with ERR below "
      "ERR_REAL and the verdict: consistent (inside the interval), optimistic (ERR_REAL above it: "
      "the grafted IMU navigates better than the real one) or pessimistic (below it).\n\n",
      r.realizations,
      r.outage_shifts > 1
          ? fmt::format(", each averaged over {} shifted outage schedules", r.outage_shifts)
          : "");
}

// The seed's Table 2/3 rows, with the predictive intervals and REAL's place when there are
// realizations.
std::string seedLayoutTable(const SgEvaluationReport& r) {
  std::string md = "## Outage errors (seed Table 2/3 layout)\n\n" + std::string(kStatHeader);
  for (const auto& s : r.solutions) {
    const auto a = asArray(s.err_rms);
    md += fmt::format("| {} |", rowName(s));
    for (int i = 0; i < 5; ++i) {
      md += " " + num(reportValue(a, i), 3);
      if (!s.draws.empty() && r.realizations > 1) {
        const PredictiveSummary& q = s.predictive.summary[i];
        const double u = i < 2 ? 1.0 : units::kRadToDeg;
        md += fmt::format(" [{}, {}]", num(q.p05 * u, 3), num(q.p95 * u, 3));
      }
      md += " |";
    }
    md += "\n";
  }
  if (!r.find("REAL")) return md + "\n";
  for (const auto& s : r.solutions) {
    if (s.label == "REAL") continue;
    const auto d = asArray(*r.diff(s.label));
    md += fmt::format("| DIFF_{} |", s.label.substr(2));
    for (int i = 0; i < 5; ++i) {
      md += " " + pct(d[i]);
      if (!s.draws.empty() && r.realizations > 1 && s.predictive.real_valid[i])
        md += fmt::format(" [{}, {}]", pct(s.predictive.diff_interval[i][0]),
                          pct(s.predictive.diff_interval[i][1]));
      md += " |";
    }
    md += "\n";
  }
  for (const auto& s : r.solutions) {
    if (s.draws.empty() || r.realizations < 2) continue;
    md += fmt::format("| REAL in SG#{} |", s.label.substr(2));
    for (int i = 0; i < 5; ++i) {
      md += s.predictive.real_valid[i]
                ? fmt::format(" {:.0f} % {} |", 100.0 * s.predictive.real_percentile[i],
                              verdictName(s.predictive.verdict[i]))
                : " n/a |";
    }
    md += "\n";
  }
  return md + "\n";
}

// realizations, outage_shifts, predictive, real_percentile, diff_interval, verdict (report units:
// m and deg for ERR, fractions for percentiles and DIFF).
void addPredictiveJson(const SgEvaluationReport& r, nlohmann::json* j) {
  (*j)["realizations"] = r.realizations;
  (*j)["outage_shifts"] = r.outage_shifts;
  (*j)["outage_shift_starts_s"] = r.shift_starts_s;
  nlohmann::json pred = nlohmann::json::object(), pct = nlohmann::json::object(),
                 dint = nlohmann::json::object(), verdict = nlohmann::json::object();
  for (const SgSolutionErrors* s : predictiveSolutions(r)) {
    const PredictiveStats& p = s->predictive;
    for (int i = 0; i < 5; ++i) {
      const std::string& name = driftStatNames()[i];
      const double u = i < 2 ? 1.0 : units::kRadToDeg;
      const PredictiveSummary& q = p.summary[i];
      pred[s->label][name] = {{"p05", q.p05 * u},
                              {"p50", q.p50 * u},
                              {"p95", q.p95 * u},
                              {"mean", q.mean * u},
                              {"sd", q.sd * u}};
      if (!p.real_valid[i]) {
        pct[s->label][name] = nullptr;
        dint[s->label][name] = nullptr;
        verdict[s->label][name] = nullptr;
        continue;
      }
      pct[s->label][name] = p.real_percentile[i];
      dint[s->label][name] = {p.diff_interval[i][0], p.diff_interval[i][1]};
      verdict[s->label][name] = verdictName(p.verdict[i]);
    }
  }
  (*j)["predictive"] = pred;
  if (r.find("REAL")) {
    (*j)["real_percentile"] = pct;
    (*j)["diff_interval"] = dint;
    (*j)["verdict"] = verdict;
  }
}

}  // namespace

namespace {

std::string statList(const std::vector<int>& idx) {
  static const std::array<const char*, 5> names{"horizontal", "vertical", "roll", "pitch",
                                                "heading"};
  std::string s;
  for (std::size_t k = 0; k < idx.size(); ++k)
    s += (k == 0 ? "" : k + 1 == idx.size() ? " and " : ", ") + std::string(names[idx[k]]);
  return s;
}

std::vector<std::string> verdictLines(const SgSolutionErrors& s) {
  std::vector<int> by[3];
  for (int i = 0; i < 5; ++i)
    if (s.predictive.real_valid[i]) by[static_cast<int>(s.predictive.verdict[i])].push_back(i);
  std::vector<std::string> out;
  const std::string sg = "SG#" + s.label.substr(2);
  if (!by[0].empty())
    out.push_back(fmt::format(
        "{} is consistent with the real IMU on {}: ERR_REAL lies inside its 90 % interval, so "
        "the differences there are realization noise.",
        sg, statList(by[0])));
  if (!by[1].empty())
    out.push_back(fmt::format(
        "{} is optimistic on {}: ERR_REAL lies above its 90 % interval, so the real IMU has an "
        "error this grafting leaves out.",
        sg, statList(by[1])));
  if (!by[2].empty())
    out.push_back(fmt::format(
        "{} is pessimistic on {}: ERR_REAL lies below its 90 % interval, so this grafting adds "
        "error the real IMU does not have.",
        sg, statList(by[2])));
  return out;
}

bool overlap(const PredictiveSummary& a, const PredictiveSummary& b) {
  return a.p05 <= b.p95 && b.p05 <= a.p95;
}

// Why SG#1 and SG#2 overlap on every statistic: the statistic where their means differ most
// (relative to SG#1's mean) against the width of SG#2's interval there. A small gap says the
// dynamic errors barely reach the outage errors; a wide interval says the case is too short.
std::string cannotTellLine(const SgSolutionErrors& sg1, const SgSolutionErrors& sg2) {
  static const std::array<const char*, 5> names{"horizontal", "vertical", "roll", "pitch",
                                                "heading"};
  int worst = 0;
  double gap = -1.0;
  for (int i = 0; i < 5; ++i) {
    const double m1 = sg1.predictive.summary[i].mean, m2 = sg2.predictive.summary[i].mean;
    const double g = m1 > 0.0 ? std::abs(m2 - m1) / m1 : 0.0;
    if (g > gap) gap = g, worst = i;
  }
  const PredictiveSummary& q = sg2.predictive.summary[worst];
  const double width = q.mean > 0.0 ? (q.p95 - q.p05) / q.mean : 0.0;
  return fmt::format(
      "This case cannot tell SG#1 from SG#2: their 90 % intervals overlap on every statistic. Their means differ "
      "by at most {:.0f} % ({}), while one realization's interval there is {:.0f} % of its mean wide{}. A longer "
      "field test, more outages or --outage-shifts narrow the intervals.",
      100.0 * gap, names[worst], 100.0 * width,
      gap < 0.1
          ? ": with this estimator the dynamic errors SG#2 adds barely change the outage errors"
          : "");
}

}  // namespace

std::vector<std::string> readingLines(const SgEvaluationReport& r) {
  std::vector<std::string> out;
  if (r.realizations < 2) {
    out.push_back(
        "One grafted realization: DIFF mixes what grafting gets wrong with the noise of one realization; "
        "run with --realizations 20 (the default) to tell them apart.");
    return out;
  }
  const SgSolutionErrors* sg1 = r.find("SG1");
  const SgSolutionErrors* sg2 = r.find("SG2");
  if (!r.find("REAL"))
    out.push_back("No real recording of the tested IMU: the intervals are the prediction itself.");
  for (const SgSolutionErrors* s : {sg2, sg1})
    if (s && r.find("REAL"))
      for (auto& l : verdictLines(*s)) out.push_back(std::move(l));
  if (sg2 && r.find("REAL")) {
    int outside = 0;
    for (int i = 0; i < 5; ++i)
      outside +=
          sg2->predictive.real_valid[i] && sg2->predictive.verdict[i] != Verdict::kConsistent;
    if (outside == 1) {
      out.push_back(
          "One statistic outside a 90 % interval is what chance gives in about every second run when "
          "grafting is exact (five statistics); a finding holds on several statistics, or again with "
          "--outage-shifts or on another drive.");
    }
  }
  if (sg1 && sg2) {
    std::vector<int> same;
    for (int i = 0; i < 5; ++i)
      if (overlap(sg1->predictive.summary[i], sg2->predictive.summary[i])) same.push_back(i);
    if (same.size() == 5) {
      out.push_back(cannotTellLine(*sg1, *sg2));
    } else {
      std::vector<int> apart;
      for (int i = 0; i < 5; ++i)
        if (std::find(same.begin(), same.end(), i) == same.end()) apart.push_back(i);
      out.push_back(fmt::format(
          "SG#1 and SG#2 are told apart on {}: their 90 % intervals do not overlap, so there "
          "the verdicts say which grafting the real IMU follows.",
          statList(apart)));
      if (!same.empty())
        out.push_back(
            fmt::format("SG#1 and SG#2 cannot be told apart on {} (their 90 % intervals overlap).",
                        statList(same)));
    }
  }
  if (sg2 && r.find("REAL") && sg2->predictive.real_valid[0]) {
    out.push_back(fmt::format(
        "A single grafted run would have reported a horizontal DIFF_2 anywhere in [{}, {}] from "
        "realization noise alone; read a single-run DIFF against that range.",
        pct(sg2->predictive.diff_interval[0][0]), pct(sg2->predictive.diff_interval[0][1])));
  }
  return out;
}

std::string driftStatsJson(const DriftStats& s, int indent) {
  return statsJson(s, false).dump(indent);
}

nlohmann::json evaluationJson(const SgEvaluationReport& r) {
  nlohmann::json j;
  j["case"] = r.case_name;
  j["estimator"] = r.estimator;
  j["outages"] = {{"count", static_cast<int>(r.outages.size())}, {"length_s", r.outage_length_s}};
  nlohmann::json err = nlohmann::json::object(), err_max = nlohmann::json::object(),
                 diff = nlohmann::json::object();
  for (const auto& s : r.solutions) {
    err[s.label] = statsJson(s.err_rms, false);
    err_max[s.label] = statsJson(s.err_max_rms, false);
  }
  j["err"] = err;  // SG: the mean over realizations (and outage schedules)
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
  addPredictiveJson(r, &j);
  return j;
}

void writeEvaluationJson(const std::string& path, const SgEvaluationReport& r) {
  writeFileAtomically(path, evaluationJson(r).dump(2) + "\n");
}

void writeTablesMarkdown(const std::string& path, const SgEvaluationReport& r) {
  std::string md;
  md += fmt::format("# Signal-grafting evaluation: {}\n\n", r.case_name);
  md += fmt::format("Estimator `{}`; {} GNSS outages of {:.0f} s; SOL_REF: {}.\n\n", r.estimator,
                    r.outages.size(), r.outage_length_s, r.reference);
  md +=
      "Statistics are the seed's: RMS over all epochs inside the outages of the error against "
      "SOL_REF (Horizontal = sqrt(dN^2 + dE^2), Vertical = |dD|); DIFF_x = |ERR_x - ERR_REAL| / "
      "ERR_REAL.\n\n";
  if (r.realizations > 1) md += predictiveIntro(r);
  md += seedLayoutTable(r);
  md += "## RMS of per-outage maximum drift (the peers' statistic)\n\n";
  md += meanTable(r, true);
  const auto& seed = seedTable(r.tested_grade);
  if (!seed.empty()) {
    md += fmt::format("## The seed's published table for a {} IMU (Niu et al. 2016)\n\n",
                      r.tested_grade == ImuGrade::kMems ? "MEMS (POS1100, Table 3)"
                                                        : "tactical (POS310, Table 2)");
    md +=
        "Different field test and IMU units: read for shape (DIFF_2 vs DIFF_1), not for equality.\n\n";
    md += "| | Horizontal | Vertical | Roll | Pitch | Heading |\n|---|---|---|---|---|---|\n";
    for (const auto& row : seed) {
      const bool is_pct = std::string(row.label).rfind("DIFF", 0) == 0;
      md += fmt::format("| {} |", row.label);
      for (double v : row.v)
        md += is_pct ? fmt::format(" {:.2f}% |", v) : fmt::format(" {:.3f} |", v);
      md += "\n";
    }
    md += "\n";
  }
  const std::vector<std::string> reading = readingLines(r);
  if (!reading.empty()) {
    md += "## Reading this result\n\n";
    for (const auto& l : reading) md += "- " + l + "\n";
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
      const auto a = asArray(k == 0 ? s.err_rms : s.err_max_rms);
      csv +=
          fmt::format("ERR_{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.label,
                      k == 0 ? "rms_over_outage_epochs" : "rms_of_outage_maxima", reportValue(a, 0),
                      reportValue(a, 1), reportValue(a, 2), reportValue(a, 3), reportValue(a, 4));
    }
  }
  for (const auto& s : r.solutions) {
    if (s.label == "REAL" || !r.find("REAL")) continue;
    const auto d = asArray(*r.diff(s.label));
    csv += fmt::format("DIFF_{},fraction,{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.label, d[0], d[1],
                       d[2], d[3], d[4]);
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
      csv +=
          fmt::format("{},{},{:.3f},{:.3f},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", s.label, i++,
                      o.window.start_s, o.window.end_s, o.epochs, reportValue(a, 0),
                      reportValue(a, 1), reportValue(a, 2), reportValue(a, 3), reportValue(a, 4));
    }
  }
  writeFileAtomically(path, csv);
}

void writePredictiveCsv(const std::string& path, const SgEvaluationReport& r) {
  std::string csv =
      "solution,statistic,unit,realizations,mean,sd,p05,p50,p95,err_real,real_percentile,diff_p05,diff_p95,verdict\n";
  const SgSolutionErrors* real = r.find("REAL");
  for (const auto& s : r.solutions) {
    if (s.draws.empty()) continue;
    for (int i = 0; i < 5; ++i) {
      const double u = i < 2 ? 1.0 : units::kRadToDeg;
      const PredictiveSummary& q = s.predictive.summary[i];
      const std::string& name = driftStatNames()[i];
      csv += fmt::format("{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}", s.label,
                         name.substr(0, name.rfind('_')), i < 2 ? "m" : "deg", q.count, q.mean * u,
                         q.sd * u, q.p05 * u, q.p50 * u, q.p95 * u);
      if (real && s.predictive.real_valid[i]) {
        csv += fmt::format(",{:.6f},{:.4f},{:.6f},{:.6f},{}\n", asArray(real->err_rms)[i] * u,
                           s.predictive.real_percentile[i], s.predictive.diff_interval[i][0],
                           s.predictive.diff_interval[i][1], verdictName(s.predictive.verdict[i]));
      } else {
        csv += ",,,,,\n";
      }
    }
  }
  writeFileAtomically(path, csv);
}

void writeSgEvaluationFiles(const std::string& out_dir, const SgEvaluationReport& rep,
                            bool errors_csv) {
  const std::filesystem::path out(out_dir);
  if (errors_csv) {
    for (const auto& s : rep.solutions)
      writeErrorsCsv((out / ("errors_" + s.label + ".csv")).string(), s.evaluation,
                     1.0 / rep.csv_rate_hz);
  }
  writeEvaluationJson((out / "evaluation.json").string(), rep);
  writeTablesMarkdown((out / "tables.md").string(), rep);
  writeEvaluationCsv((out / "evaluation.csv").string(), rep);
  writePredictiveCsv((out / "predictive.csv").string(), rep);
  writePerOutageCsv((out / "outage_drift.csv").string(), rep);
}

}  // namespace graftnav
