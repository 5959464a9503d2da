#include "batch_summary.h"

#include <fmt/core.h>

#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "graftnav/io/atomic_file.h"
#include "graftnav/sg/sg_statistics.h"

namespace graftnav::app {
namespace fs = std::filesystem;
namespace {

using Five = std::array<double, 5>;

Five nanFive() {
  Five a;
  a.fill(std::numeric_limits<double>::quiet_NaN());
  return a;
}

std::string cell(double v, int digits) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "";
}

// ERR (outage RMS, m and deg) or DIFF (fraction) of one solution, in driftStatNames() order.
Five values(const BatchSummaryRow& r, const std::string& solution, bool diff) {
  Five a = nanFive();
  if (r.status != TaskStatus::kOk) return a;
  const auto& names = driftStatNames();
  for (const auto& s : r.statistics) {
    if (s.solution != solution) continue;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (s.statistic != names[i]) continue;
      a[i] = diff ? s.diff.value_or(std::numeric_limits<double>::quiet_NaN()) : s.outage_rms;
    }
  }
  return a;
}

const std::vector<std::pair<std::string, bool>>& summaryColumns() {
  static const std::vector<std::pair<std::string, bool>> cols{
      {"SG1", false}, {"SG2", false}, {"REAL", false}, {"SG1", true}, {"SG2", true}};
  return cols;
}

std::string statusText(const BatchSummaryRow& r) {
  if (r.status == TaskStatus::kOk) return "ok";
  if (r.status == TaskStatus::kMissing) return "missing (no record)";
  return "failed: " + r.error;
}

void writeTaskSummaries(const std::string& out_dir, const std::vector<BatchSummaryRow>& rows) {
  std::string csv = "case,estimator,outages,seed,outage_count,status";
  for (const auto& [l, d] : summaryColumns())
    for (const auto& n : driftStatNames())
      csv += fmt::format(",{}_{}_{}", d ? "DIFF" : "ERR", l,
                         d ? n.substr(0, n.rfind('_')) + "_frac" : n);
  csv += ",error\n";
  std::string md =
      "# graftnav batch summary\n\nERR: RMS over outage epochs (m, deg); DIFF: |ERR_x - ERR_REAL| "
      "/ ERR_REAL.\n\n";
  md +=
      "| case | estimator | outages | seed | n | ERR_SG1 h/v/hdg | ERR_SG2 h/v/hdg | ERR_REAL "
      "h/v/hdg | DIFF_1 h/v/hdg | "
      "DIFF_2 h/v/hdg | status |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const std::string n = r.outage_count ? std::to_string(*r.outage_count) : "";
    csv += fmt::format("{},{},{},{},{},{}", r.case_name, r.estimator, r.schedule, r.seed, n,
                       statusName(r.status));
    for (const auto& [l, d] : summaryColumns())
      for (double v : values(r, l, d)) csv += "," + cell(v, 6);
    std::string err = r.error;
    for (char& ch : err)
      if (ch == ',' || ch == '\n') ch = ';';
    csv += "," + err + "\n";
    md += fmt::format("| {} | {} | {} | {} | {} |", r.case_name, r.estimator, r.schedule, r.seed,
                      n.empty() ? "-" : n);
    for (const auto& [l, d] : summaryColumns()) {
      const auto v = values(r, l, d);
      if (!std::isfinite(v[0])) {
        md += " - |";
      } else if (d) {
        md += fmt::format(" {:.1f}% / {:.1f}% / {:.1f}% |", 100 * v[0], 100 * v[1], 100 * v[4]);
      } else {
        md += fmt::format(" {:.3f} / {:.3f} / {:.4f} |", v[0], v[1], v[4]);
      }
    }
    std::string status = statusText(r);
    for (char& ch : status)
      if (ch == '\n' || ch == '|') ch = ' ';
    md += " " + status + " |\n";
  }
  writeFileAtomically((fs::path(out_dir) / "summary.csv").string(), csv);
  writeFileAtomically((fs::path(out_dir) / "summary.md").string(), md);
}

struct Experiment {
  std::string name, estimator, schedule;
  std::vector<const BatchSummaryRow*> runs;
};

// Mean and standard deviation over the realizations of ERR rows, then DIFF of the means; this
// separates what grafting gets wrong from the spread of single realizations.
// The finished tasks grouped into experiments, in order of first appearance.
std::vector<Experiment> groupExperiments(const std::vector<BatchSummaryRow>& rows) {
  std::map<std::string, std::size_t> index;
  std::vector<Experiment> groups;
  for (const auto& r : rows) {
    if (r.status != TaskStatus::kOk) continue;
    const std::string exp = experimentName(r.case_name);
    const std::string key = exp + "|" + r.estimator + "|" + r.schedule;
    if (!index.count(key)) {
      index[key] = groups.size();
      groups.push_back(Experiment{exp, r.estimator, r.schedule, {}});
    }
    groups[index[key]].runs.push_back(&r);
  }
  return groups;
}

void writeMonteCarloSummary(const std::string& out_dir, const std::vector<BatchSummaryRow>& rows) {
  const std::vector<Experiment> groups = groupExperiments(rows);
  bool any = false;
  for (const auto& g : groups) any = any || g.runs.size() > 1;
  if (!any) {  // no experiment with realizations: no Monte-Carlo table (and none left from before)
    fs::remove(fs::path(out_dir) / "summary_monte_carlo.md");
    fs::remove(fs::path(out_dir) / "summary_monte_carlo.csv");
    return;
  }
  std::string md =
      "# graftnav batch: Monte-Carlo summary over seeds\n\n"
      "Mean (and standard deviation over seeds) of the seed's outage statistic; DIFF on the "
      "means.\n\n"
      "| experiment | estimator | outages | seeds | row | horizontal_m | vertical_m | roll_deg | "
      "pitch_deg | heading_deg |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  std::string csv =
      "experiment,estimator,outages,seeds,row,horizontal_m,vertical_m,roll_deg,pitch_deg,heading_"
      "deg\n";
  for (const Experiment& g : groups) {
    if (g.runs.size() < 2) continue;
    std::map<std::string, Five> mean;
    for (const std::string label : {"SG1", "SG2", "REAL"}) {
      Five m{}, sq{};
      int n = 0;
      for (const BatchSummaryRow* r : g.runs) {
        const auto v = values(*r, label, false);
        if (!std::isfinite(v[0])) continue;
        ++n;
        for (int i = 0; i < 5; ++i) {
          m[i] += v[i];
          sq[i] += v[i] * v[i];
        }
      }
      if (n == 0) continue;
      Five sd{};
      for (int i = 0; i < 5; ++i) {
        m[i] /= n;
        sd[i] = n > 1 ? std::sqrt(std::max(0.0, (sq[i] - n * m[i] * m[i]) / (n - 1))) : 0.0;
      }
      mean[label] = m;
      md +=
          fmt::format("| {} | {} | {} | {} | ERR_{} |", g.name, g.estimator, g.schedule, n, label);
      csv += fmt::format("{},{},{},{},ERR_{}_mean", g.name, g.estimator, g.schedule, n, label);
      for (int i = 0; i < 5; ++i) {
        md += fmt::format(" {:.4f} ({:.4f}) |", m[i], sd[i]);
        csv += fmt::format(",{:.6f}", m[i]);
      }
      md += "\n";
      csv += "\n";
    }
    if (!mean.count("REAL")) continue;
    for (const std::string label : {"SG1", "SG2"}) {
      if (!mean.count(label)) continue;
      md += fmt::format("| {} | {} | {} | {} | DIFF_{} (of means) |", g.name, g.estimator,
                        g.schedule, g.runs.size(), label.substr(2));
      csv += fmt::format("{},{},{},{},DIFF_{}_of_means", g.name, g.estimator, g.schedule,
                         g.runs.size(), label.substr(2));
      for (int i = 0; i < 5; ++i) {
        const double d = std::abs(mean[label][i] - mean["REAL"][i]) / mean["REAL"][i];
        md += fmt::format(" {:.1f}% |", 100.0 * d);
        csv += fmt::format(",{:.6f}", d);
      }
      md += "\n";
      csv += "\n";
    }
  }
  writeFileAtomically((fs::path(out_dir) / "summary_monte_carlo.md").string(), md);
  writeFileAtomically((fs::path(out_dir) / "summary_monte_carlo.csv").string(), csv);
}

}  // namespace

std::string experimentName(const std::string& case_name) {
  const auto pos = case_name.rfind("_seed");
  if (pos == std::string::npos || pos + 5 >= case_name.size()) return case_name;
  for (std::size_t i = pos + 5; i < case_name.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(case_name[i]))) return case_name;
  return case_name.substr(0, pos);
}

void writeBatchSummaries(const std::string& out_dir, const std::vector<BatchSummaryRow>& rows) {
  writeTaskSummaries(out_dir, rows);
  writeMonteCarloSummary(out_dir, rows);
}

}  // namespace graftnav::app
