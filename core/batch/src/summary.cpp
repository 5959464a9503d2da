#include "graftnav/batch/summary.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "graftnav/io/atomic_file.h"

namespace graftnav {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One cell of a group's table: a few statistics of one solution ("" = the task's estimator),
// joined by " / ".
struct Column {
  std::string header, solution, scope, measure;
  std::vector<std::string> statistics;
  int digits = 3;
  bool percent = false;
};

std::vector<Column> columnsOf(BatchCommand command) {
  const std::vector<std::string> hvy{"horizontal_m", "vertical_m", "heading_deg"};
  if (command == BatchCommand::kEvaluate || command == BatchCommand::kRealSg) {
    std::vector<Column> c;
    for (const char* s : {"SG1", "SG2", "REAL"})
      c.push_back({fmt::format("ERR_{} h/v/hdg", s), s, "outage", "rms", hvy});
    for (const char* s : {"SG1", "SG2"})
      c.push_back({fmt::format("DIFF_{} h/v/hdg", s + 2), s, "outage", "diff", hvy, 1, true});
    return c;
  }
  if (command == BatchCommand::kNavigate)
    return {{"outage RMS h/v/hdg", "", "outage", "rms", hvy},
            {"RMS of outage max h", "", "outage", "max_rms", {"horizontal_m"}},
            {"overall RMS h", "", "overall", "rms", {"horizontal_m"}},
            {"NEES", "", "overall", "mean", {"nees"}, 2}};
  if (command == BatchCommand::kReal)
    return {{"check points", "", "checkpoint", "count", {"points"}, 0},
            {"check point RMS h/v", "", "checkpoint", "rms", {"horizontal_m", "vertical_m"}},
            {"check point RMS of max h", "", "checkpoint", "max_rms", {"horizontal_m"}},
            {"vs reference: outage RMS h", "", "reference", "rms", {"horizontal_m"}}};
  if (command == BatchCommand::kDiagnose)
    return {{"DIFF before (SG2) h/v/hdg", "SG2", "outage", "diff", hvy, 1, true},
            {"DIFF after (SG3) h/v/hdg", "SG3", "outage", "diff", hvy, 1, true}};
  return {};  // compare: its own cells (compareCells)
}

std::string number(double v, int digits, bool percent) {
  if (!std::isfinite(v)) return "-";
  return percent ? fmt::format("{:.{}f}%", 100.0 * v, digits) : fmt::format("{:.{}f}", v, digits);
}

std::string cellOf(const BatchTaskResult& r, const Column& c) {
  std::string out;
  for (const auto& s : c.statistics) {
    const double v =
        statisticValue(r, c.solution.empty() ? r.estimator : c.solution, c.scope, s, c.measure);
    const int digits = s == "heading_deg" && !c.percent ? c.digits + 1 : c.digits;
    out += (out.empty() ? "" : " / ") + number(v, digits, c.percent);
  }
  return out;
}

// compare: each estimator's outage RMS h, and each pair's largest normalized difference.
std::pair<std::string, std::string> compareCells(const BatchTaskResult& r) {
  std::string est, pairs;
  for (const auto& s : r.statistics) {
    if (s.scope == "outage" && s.measure == "rms" && s.statistic == "horizontal_m")
      est += fmt::format("{}{} {:.3f}", est.empty() ? "" : ", ", s.solution, s.value);
  }
  std::map<std::string, double> z;
  for (const auto& c : r.cross_checks) {
    const std::string key = c.a + "-" + c.b;
    const double v = c.max_normalized.value_or(kNaN);
    if (!z.count(key) || (std::isfinite(v) && !(z[key] >= v))) z[key] = v;
  }
  for (const auto& [k, v] : z)
    pairs += fmt::format("{}{} {}", pairs.empty() ? "" : ", ", k,
                         std::isfinite(v) ? fmt::format("{:.1f}", v) : std::string("no sigma"));
  return {est.empty() ? "-" : est, pairs.empty() ? "-" : pairs};
}

std::string oneLine(std::string s) {
  for (char& ch : s)
    if (ch == '\n' || ch == '|') ch = ' ';
  return s;
}

std::string statusText(const BatchTaskResult& r) {
  if (r.status == TaskStatus::kOk) return "ok";
  if (r.status == TaskStatus::kMissing) return "missing (no record)";
  return "failed: " + oneLine(r.error);
}

std::string groupTable(const std::vector<BatchTaskResult>& rows, const std::string& grp) {
  const BatchTaskResult* first = nullptr;
  for (const auto& r : rows)
    if (r.grp == grp) first = first ? first : &r;
  const BatchCommand command = first->command;
  const std::string command_name = batchCommandName(command);
  const std::vector<Column> cols = columnsOf(command);
  std::string md = fmt::format("## {}{}\n\n| case | estimator | outages | seed | options | n |",
                               grp, grp == command_name ? "" : " (" + command_name + ")");
  std::string rule = "|---|---|---|---|---|---|";
  for (const auto& c : cols) md += " " + c.header + " |";
  if (command == BatchCommand::kCompare) md += " outage RMS h | cross-check max |d|/sigma |";
  if (command == BatchCommand::kDiagnose) md += " effect parameters |";
  md += " status |\n";
  const std::size_t extra = cols.size() + (command == BatchCommand::kCompare ? 2 : 0) +
                            (command == BatchCommand::kDiagnose);
  for (std::size_t i = 0; i <= extra; ++i) rule += "---|";
  md += rule + "\n";
  for (const auto& r : rows) {
    if (r.grp != grp) continue;
    md += fmt::format("| {} | {} | {} | {} | {} | {} |", r.case_name, r.estimator, r.schedule,
                      r.seed ? std::to_string(*r.seed) : "-",
                      r.options_json == "{}" ? "-" : r.options_json,
                      r.outage_count ? std::to_string(*r.outage_count) : "-");
    for (const auto& c : cols) md += " " + cellOf(r, c) + " |";
    if (command == BatchCommand::kCompare) {
      const auto [est, pairs] = compareCells(r);
      md += " " + est + " | " + pairs + " |";
    }
    if (command == BatchCommand::kDiagnose) md += fmt::format(" {} |", r.effects);
    md += " " + statusText(r) + " |\n";
  }
  return md + "\n";
}

void writeTaskSummaries(const std::string& out_dir, const std::vector<BatchTaskResult>& rows) {
  std::string csv =
      "task_index,group,command,case,estimator,schedule,seed,options,status,solution,scope,"
      "statistic,measure,value,unit,error\n";
  for (const auto& r : rows) {
    const std::string head = fmt::format(
        "{},{},{},{},{},{},{},{},{}", r.task_index, csvField(r.grp), batchCommandName(r.command),
        csvField(r.case_name), csvField(r.estimator), r.schedule,
        r.seed ? std::to_string(*r.seed) : "", csvField(r.options_json), statusName(r.status));
    if (r.statistics.empty() || r.status != TaskStatus::kOk)
      csv += head + ",,,,,,," + csvField(r.error) + "\n";
    if (r.status != TaskStatus::kOk) continue;
    for (const auto& s : r.statistics)
      csv += fmt::format("{},{},{},{},{},{:.6f},{},\n", head, s.solution, s.scope, s.statistic,
                         s.measure, s.value, s.unit);
  }
  std::string md =
      "# graftnav batch summary\n\nOne table per group. Outage RMS over outage epochs (m, deg); "
      "DIFF = |ERR_x - ERR_REAL| / ERR_REAL; every statistic of every task is in summary.csv and "
      "results.sqlite.\n\n";
  std::vector<std::string> groups;
  for (const auto& r : rows)
    if (groups.empty() || groups.back() != r.grp) groups.push_back(r.grp);
  std::vector<std::string> seen;
  for (const auto& g : groups) {
    if (std::find(seen.begin(), seen.end(), g) != seen.end()) continue;
    seen.push_back(g);
    md += groupTable(rows, g);
  }
  writeFileAtomically((fs::path(out_dir) / "summary.csv").string(), csv);
  writeFileAtomically((fs::path(out_dir) / "summary.md").string(), md);
}

struct Experiment {
  std::string grp, name, estimator, schedule, options;
  std::vector<const BatchTaskResult*> runs;
};

// The finished evaluate / real-sg tasks grouped into experiments, in order of first appearance.
std::vector<Experiment> groupExperiments(const std::vector<BatchTaskResult>& rows) {
  std::map<std::string, std::size_t> index;
  std::vector<Experiment> groups;
  for (const auto& r : rows) {
    if (r.status != TaskStatus::kOk ||
        (r.command != BatchCommand::kEvaluate && r.command != BatchCommand::kRealSg))
      continue;
    const std::string exp = experimentName(r.case_name);
    const std::string key =
        r.grp + "|" + exp + "|" + r.estimator + "|" + r.schedule + "|" + r.options_json;
    if (!index.count(key)) {
      index[key] = groups.size();
      groups.push_back(Experiment{r.grp, exp, r.estimator, r.schedule, r.options_json, {}});
    }
    groups[index[key]].runs.push_back(&r);
  }
  return groups;
}

const std::array<const char*, 5> kDrift{"horizontal_m", "vertical_m", "roll_deg", "pitch_deg",
                                        "heading_deg"};

// Mean (and SD over seeds) of the seed's outage ERR per solution; DIFF of the means.
void addExperiment(const Experiment& g, std::string* md, std::string* csv) {
  std::map<std::string, std::array<double, 5>> mean;
  const std::string who = fmt::format("{} | {} | {} | {} | {}", g.grp, g.name, g.estimator,
                                      g.schedule, g.options == "{}" ? "-" : g.options);
  const std::string who_csv = fmt::format("{},{},{},{},{}", csvField(g.grp), csvField(g.name),
                                          csvField(g.estimator), g.schedule, csvField(g.options));
  for (const std::string label : {"SG1", "SG2", "REAL"}) {
    std::array<double, 5> m{}, sq{};
    int n = 0;
    for (const BatchTaskResult* r : g.runs) {
      if (!std::isfinite(statisticValue(*r, label, "outage", kDrift[0], "rms"))) continue;
      ++n;
      for (int i = 0; i < 5; ++i) {
        const double v = statisticValue(*r, label, "outage", kDrift[i], "rms");
        m[i] += v;
        sq[i] += v * v;
      }
    }
    if (n == 0) continue;
    *md += fmt::format("| {} | {} | ERR_{} |", who, n, label);
    *csv += fmt::format("{},{},ERR_{}_mean", who_csv, n, label);
    for (int i = 0; i < 5; ++i) {
      m[i] /= n;
      const double sd = n > 1 ? std::sqrt(std::max(0.0, (sq[i] - n * m[i] * m[i]) / (n - 1))) : 0.0;
      *md += fmt::format(" {:.4f} ({:.4f}) |", m[i], sd);
      *csv += fmt::format(",{:.6f}", m[i]);
    }
    mean[label] = m;
    *md += "\n";
    *csv += "\n";
  }
  if (!mean.count("REAL")) return;
  for (const std::string label : {"SG1", "SG2"}) {
    if (!mean.count(label)) continue;
    *md += fmt::format("| {} | {} | DIFF_{} (of means) |", who, g.runs.size(), label.substr(2));
    *csv += fmt::format("{},{},DIFF_{}_of_means", who_csv, g.runs.size(), label.substr(2));
    for (int i = 0; i < 5; ++i) {
      const double d = std::abs(mean[label][i] - mean["REAL"][i]) / mean["REAL"][i];
      *md += fmt::format(" {:.1f}% |", 100.0 * d);
      *csv += fmt::format(",{:.6f}", d);
    }
    *md += "\n";
    *csv += "\n";
  }
}

void writeMonteCarloSummary(const std::string& out_dir, const std::vector<BatchTaskResult>& rows) {
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
      "| group | experiment | estimator | outages | options | seeds | row | horizontal_m | "
      "vertical_m | roll_deg | pitch_deg | heading_deg |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::string csv =
      "group,experiment,estimator,outages,options,seeds,row,horizontal_m,vertical_m,roll_deg,"
      "pitch_deg,heading_deg\n";
  for (const Experiment& g : groups)
    if (g.runs.size() > 1) addExperiment(g, &md, &csv);
  writeFileAtomically((fs::path(out_dir) / "summary_monte_carlo.md").string(), md);
  writeFileAtomically((fs::path(out_dir) / "summary_monte_carlo.csv").string(), csv);
}

}  // namespace

double statisticValue(const BatchTaskResult& r, const std::string& solution,
                      const std::string& scope, const std::string& statistic,
                      const std::string& measure) {
  if (r.status != TaskStatus::kOk) return kNaN;
  for (const auto& s : r.statistics)
    if (s.solution == solution && s.scope == scope && s.statistic == statistic &&
        s.measure == measure)
      return s.value;
  return kNaN;
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string experimentName(const std::string& case_name) {
  const auto pos = case_name.rfind("_seed");
  if (pos == std::string::npos || pos + 5 >= case_name.size()) return case_name;
  for (std::size_t i = pos + 5; i < case_name.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(case_name[i]))) return case_name;
  return case_name.substr(0, pos);
}

void writeBatchSummaries(const std::string& out_dir, const std::vector<BatchTaskResult>& rows) {
  writeTaskSummaries(out_dir, rows);
  writeMonteCarloSummary(out_dir, rows);
}

}  // namespace graftnav
