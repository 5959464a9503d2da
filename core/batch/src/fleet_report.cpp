#include "graftnav/batch/fleet_report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "graftnav/batch/summary.h"
#include "graftnav/io/atomic_file.h"

namespace graftnav {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool isFleetScope(const std::string& scope) {
  return scope == "outage" || scope == "checkpoint" || scope == "reference";
}

// Values collected under a key, kept in order of first appearance.
template <typename Key>
struct Collector {
  std::vector<Key> order;
  std::map<Key, std::vector<double>> values;
  void add(const Key& k, double v) {
    if (!values.count(k)) order.push_back(k);
    if (std::isfinite(v)) values[k].push_back(v);
  }
};

struct Spread {
  std::size_t n = 0;
  double min = kNaN, p25 = kNaN, median = kNaN, p75 = kNaN, max = kNaN, mean = kNaN, sd = kNaN;
};

Spread spreadOf(std::vector<double> v) {
  Spread s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  s.p25 = quantileOfSorted(v, 0.25);
  s.median = quantileOfSorted(v, 0.5);
  s.p75 = quantileOfSorted(v, 0.75);
  double sum = 0.0, sq = 0.0;
  for (double x : v) sum += x;
  s.mean = sum / v.size();
  for (double x : v) sq += (x - s.mean) * (x - s.mean);
  s.sd = v.size() > 1 ? std::sqrt(sq / (v.size() - 1)) : 0.0;
  return s;
}

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.6f}", v) : ""; }

std::string options(const std::string& json) { return json == "{}" ? "-" : json; }

// --- per estimator -------------------------------------------------------------------------
using EstimatorKey = std::array<std::string, 10>;  // grp command options schedule estimator
                                                   // solution scope statistic measure unit

std::string estimatorsReport(const std::vector<BatchTaskResult>& rows, std::string* csv) {
  Collector<EstimatorKey> c;
  for (const auto& r : rows) {
    if (r.status != TaskStatus::kOk) continue;
    for (const auto& s : r.statistics) {
      if (!isFleetScope(s.scope) || s.measure == "count") continue;
      c.add({r.grp, batchCommandName(r.command), r.options_json, r.schedule, s.estimator,
             s.solution, s.scope, s.statistic, s.measure, s.unit},
            s.value);
    }
  }
  *csv =
      "group,command,options,schedule,estimator,solution,scope,statistic,measure,unit,n,min,p25,"
      "median,p75,max,mean\n";
  std::string md =
      "## Per estimator: outage statistics across the cases\n\nMedian [p25, p75] (min - max) "
      "over the cases and seeds of each group's RMS over the outage epochs (`outage`, against "
      "the truth or SOL_REF), the check points (`checkpoint`) and the reference solution "
      "(`reference`). Every statistic and measure is in report_estimators.csv.\n\n"
      "| group | options | outages | estimator | solution | scope | n | horizontal (m) | "
      "vertical (m) | heading (deg) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  std::map<std::string, std::string> cells;  // headline row -> its cells by statistic
  std::vector<std::string> headline;
  for (const auto& k : c.order) {
    const Spread s = spreadOf(c.values[k]);
    for (std::size_t i = 0; i < k.size(); ++i) *csv += (i ? "," : "") + csvField(k[i]);
    *csv += fmt::format(",{},{},{},{},{},{},{}\n", s.n, num(s.min), num(s.p25), num(s.median),
                        num(s.p75), num(s.max), num(s.mean));
    if (k[8] != "rms" || s.n == 0) continue;
    const std::string row = fmt::format("| {} | {} | {} | {} | {} | {} | {} |", k[0], options(k[2]),
                                        k[3], k[4], k[5], k[6], s.n);
    if (!cells.count(row)) headline.push_back(row);
    const int d = k[7] == "heading_deg" ? 4 : 3;
    cells[row + k[7]] = fmt::format("{:.{}f} [{:.{}f}, {:.{}f}] ({:.{}f} - {:.{}f})", s.median, d,
                                    s.p25, d, s.p75, d, s.min, d, s.max, d);
    cells[row] = "";
  }
  for (const auto& row : headline) {
    md += row;
    for (const char* st : {"horizontal_m", "vertical_m", "heading_deg"})
      md += " " + (cells.count(row + st) ? cells[row + st] : std::string("-")) + " |";
    md += "\n";
  }
  return md + "\n";
}

// --- options sweeps ------------------------------------------------------------------------
using OptionKey = std::array<std::string, 10>;  // grp option value estimator solution scope
                                                // statistic measure unit command

std::string optionsReport(const std::vector<BatchTaskResult>& rows, std::string* csv) {
  Collector<OptionKey> c;
  for (const auto& r : rows) {
    if (r.status != TaskStatus::kOk || r.options_json == "{}") continue;
    const nlohmann::ordered_json o = nlohmann::ordered_json::parse(r.options_json);
    for (const auto& [key, value] : o.items()) {
      for (const auto& s : r.statistics) {
        if (!isFleetScope(s.scope) || s.measure == "count") continue;
        c.add({r.grp, key, value.dump(), s.estimator, s.solution, s.scope, s.statistic, s.measure,
               s.unit, batchCommandName(r.command)},
              s.value);
      }
    }
  }
  *csv =
      "group,option,value,estimator,solution,scope,statistic,measure,unit,command,n,mean,sd,min,"
      "max\n";
  std::string md =
      "## Options sweeps\n\nOutage RMS horizontal (m) against each option value: mean +- SD "
      "over cases and seeds (min - max); every statistic in report_options.csv.\n\n";
  bool any = false;
  for (const auto& k : c.order) {
    const Spread s = spreadOf(c.values[k]);
    for (std::size_t i = 0; i < k.size(); ++i) *csv += (i ? "," : "") + csvField(k[i]);
    *csv += fmt::format(",{},{},{},{},{}\n", s.n, num(s.mean), num(s.sd), num(s.min), num(s.max));
    if (k[7] != "rms" || k[6] != "horizontal_m" || s.n == 0) continue;
    if (!any)
      md +=
          "| group | option | value | estimator | solution | scope | n | horizontal (m) |\n"
          "|---|---|---|---|---|---|---|---|\n";
    any = true;
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.3f} +- {:.3f} ({:.3f} - {:.3f}) |\n",
                      k[0], k[1], k[2], k[3], k[4], k[5], s.n, s.mean, s.sd, s.min, s.max);
  }
  if (!any) md += "No group sweeps an option.\n";
  return md + "\n";
}

// --- cross-check ---------------------------------------------------------------------------
std::string formText(const std::string& form) {
  if (form == "filter-smoother")
    return "filter-smoother: sigma = sqrt(P_a - P_b), b smooths a's own forward filter (exact)";
  if (form == "sum-upper-bound")
    return "sum-upper-bound: sigma = sqrt(P_a + P_b), an upper bound for estimators whose errors "
           "are positively correlated, so |d|/sigma is understated and agreement over-stated";
  return "none: an estimator of the pair gives no sigma; differences only";
}

std::string crossCheckReport(const std::vector<BatchTaskResult>& rows, std::string* csv) {
  *csv =
      "group,case,options,schedule,a,b,sigma_form,statistic,rms_difference,rms_sigma,"
      "rms_normalized,max_normalized,epochs,beyond_3_sigma\n";
  std::map<std::string, std::string> forms;                          // pair -> form
  std::map<std::string, std::vector<std::string>> beyond, no_sigma;  // pair -> cases
  std::vector<std::string> pairs;
  for (const auto& r : rows) {
    if (r.status != TaskStatus::kOk) continue;
    std::map<std::string, double> worst;
    for (const auto& x : r.cross_checks) {
      const std::string pair = x.a + " - " + x.b;
      if (!forms.count(pair)) pairs.push_back(pair);
      forms[pair] = x.sigma_form;
      const double z = x.max_normalized.value_or(kNaN);
      const bool out = std::isfinite(z) && z > kCrossCheckLimitSigma;
      *csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", csvField(r.grp),
                          csvField(r.case_name), csvField(r.options_json), r.schedule, x.a, x.b,
                          x.sigma_form, x.statistic, num(x.rms_difference.value_or(kNaN)),
                          num(x.rms_sigma.value_or(kNaN)), num(x.rms_normalized.value_or(kNaN)),
                          num(z), x.epochs, out ? "yes" : "no");
      if (out && !(worst[pair] >= z)) worst[pair] = z;
      if (x.sigma_form == "none" && x.statistic == "horizontal_m")
        no_sigma[pair].push_back(r.case_name);
    }
    for (const auto& [pair, z] : worst)
      beyond[pair].push_back(fmt::format("{} ({:.1f} sigma)", r.case_name, z));
  }
  std::string md =
      "## Fleet cross-check: estimators against each other inside the outages\n\nFrom the compare "
      "tasks: the largest |difference| / sigma of the difference over the outage epochs "
      "(horizontal, vertical, heading); a case is listed when it exceeds 3.\n\n";
  if (pairs.empty()) return md + "No compare task finished.\n\n";
  md += "| pair | sigma of the difference | cases beyond 3 sigma |\n|---|---|---|\n";
  for (const auto& p : pairs) {
    std::string list;
    for (const auto& c : beyond[p]) list += (list.empty() ? "" : ", ") + c;
    if (forms[p] == "none")
      list = "not weighed (no sigma) in " + std::to_string(no_sigma[p].size()) + " case(s)";
    md += fmt::format("| {} | {} | {} |\n", p, formText(forms[p]), list.empty() ? "none" : list);
  }
  return md + "\n";
}

// --- failed --------------------------------------------------------------------------------
std::string failedReport(const std::vector<BatchTaskResult>& rows, std::string* csv) {
  *csv = "task_index,group,command,case,estimator,schedule,seed,options,status,error\n";
  std::string md = "## Failed tasks\n\n";
  int n = 0;
  for (const auto& r : rows) {
    if (r.status == TaskStatus::kOk) continue;
    ++n;
    *csv += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", r.task_index, csvField(r.grp),
                        batchCommandName(r.command), csvField(r.case_name), csvField(r.estimator),
                        r.schedule, r.seed ? std::to_string(*r.seed) : "", csvField(r.options_json),
                        statusName(r.status), csvField(r.error));
    std::string msg =
        r.status == TaskStatus::kMissing ? "no record (never ran or killed)" : r.error;
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    md += fmt::format("- `{}` ({}): {}\n", r.name, statusName(r.status), msg);
  }
  return md + (n == 0 ? "None.\n" : "") + "\n";
}

}  // namespace

double quantileOfSorted(const std::vector<double>& v, double q) {
  if (v.empty()) return kNaN;
  const double pos = q * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

void writeFleetReports(const std::string& out_dir, const std::vector<BatchTaskResult>& rows) {
  std::string est_csv, opt_csv, cc_csv, failed_csv;
  std::string md = "# graftnav batch: fleet report\n\n";
  md += estimatorsReport(rows, &est_csv);
  md += optionsReport(rows, &opt_csv);
  md += crossCheckReport(rows, &cc_csv);
  md += failedReport(rows, &failed_csv);
  const fs::path d(out_dir);
  writeFileAtomically((d / "report_estimators.csv").string(), est_csv);
  writeFileAtomically((d / "report_options.csv").string(), opt_csv);
  writeFileAtomically((d / "report_crosscheck.csv").string(), cc_csv);
  writeFileAtomically((d / "report_failed.csv").string(), failed_csv);
  writeFileAtomically((d / "report.md").string(), md);
}

}  // namespace graftnav
