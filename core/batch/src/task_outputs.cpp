#include "graftnav/batch/task_outputs.h"

#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace graftnav {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* const kDriftNames[] = {"horizontal_m", "vertical_m", "roll_deg", "pitch_deg",
                                   "heading_deg"};

json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(fmt::format("'{}' not written by the task's command", path.string()));
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("'{}' is not valid JSON: {}", path.string(), e.what()));
  }
}

std::optional<double> number(const json& o, const char* key) {
  if (!o.is_object()) return std::nullopt;
  const auto it = o.find(key);
  if (it == o.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

std::string unitOf(const std::string& statistic) {
  return statistic.size() > 4 && statistic.compare(statistic.size() - 4, 4, "_deg") == 0 ? "deg"
                                                                                         : "m";
}

// Adds one row when the number is there (a null in the file is an absent statistic, no row).
struct Rows {
  BatchRunRecord* r;
  void add(const std::string& est, const std::string& sol, const char* scope,
           const std::string& statistic, const char* measure, std::optional<double> v,
           const std::string& unit) {
    if (v) r->statistics.push_back({est, solutionLabel(sol), scope, statistic, measure, *v, unit});
  }
  // {horizontal_m: .., vertical_m: .., roll_deg: .., ...} as five rows.
  void drift(const std::string& est, const std::string& sol, const char* scope, const char* measure,
             const json& o, bool fraction = false) {
    for (const char* name : kDriftNames)
      add(est, sol, scope, name, measure, number(o, name), fraction ? "frac" : unitOf(name));
  }
};

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : "+") + x;
  return s;
}

// outage_drift.csv of navigate (index, ...) and of evaluate/real-sg (solution, outage, ...).
void readOutageDrift(const fs::path& path, const std::string& estimator, BatchRunRecord* r) {
  std::ifstream in(path);
  if (!in) return;
  std::string header, line;
  std::getline(in, header);
  const bool per_solution = header.rfind("solution,", 0) == 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::vector<std::string> f;
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    const std::size_t o = per_solution ? 1 : 0;
    if (f.size() < o + 9)
      throw std::runtime_error(fmt::format("'{}': short line '{}'", path.string(), line));
    auto d = [&](std::size_t i) { return f[o + i].empty() ? std::nan("") : std::stod(f[o + i]); };
    r->outages.push_back({per_solution ? solutionLabel(f[0]) : estimator, std::stoi(f[o]), d(1),
                          d(2), std::stoi(f[o + 3]), d(4), d(5), d(6), d(7), d(8)});
  }
}

void readNavigate(const fs::path& dir, const std::string& est, BatchRunRecord* r) {
  const fs::path errors = dir / "errors.json";
  if (fs::exists(errors)) {  // navigate writes it only with a truth or reference
    const json j = readJson(errors);
    Rows rows{r};
    const json& o = j.value("overall", json::object());
    for (const char* name : kDriftNames) {  // overall keys say rms in the middle: horizontal_rms_m
      const std::string s(name), unit = unitOf(s);
      const std::string key = s.substr(0, s.rfind('_')) + "_rms_" + unit;
      rows.add(est, est, "overall", s, "rms", number(o, key.c_str()), unit);
    }
    rows.drift(est, est, "outage", "rms", j.value("outage", json::object()));
    rows.drift(est, est, "outage", "max_rms", j.value("outage_max", json::object()));
    rows.add(est, est, "overall", "nees", "mean", number(j, "nees"), "1");
    if (auto n = number(j.value("outages", json::object()), "count")) r->outage_count = int(*n);
  }
  const json info = readJson(dir / "run_info.json");
  if (const auto w = info.find("outage_windows_s"); w != info.end() && w->is_array())
    r->outage_count = static_cast<int>(w->size());
  r->reference = info.value("reference", std::string());
  readOutageDrift(dir / "outage_drift.csv", est, r);
}

void readCompare(const fs::path& dir, BatchRunRecord* r) {
  const json j = readJson(dir / "compare.json");
  Rows rows{r};
  const json estimators = j.value("estimators", json::array());
  for (const json& e : estimators) {
    const std::string name = e.value("name", std::string());
    rows.drift(name, name, "outage", "rms", e.value("outage_rms", json::object()));
    rows.drift(name, name, "outage", "max_rms", e.value("outage_max_rms", json::object()));
    rows.drift(name, name, "overall", "rms", e.value("overall_rms", json::object()));
  }
  if (auto n = number(j, "outage_count")) r->outage_count = static_cast<int>(*n);
  const json differences = j.value("differences", json::array());
  for (const json& d : differences) {
    const json cc = d.value("cross_check", json::object());
    for (const char* name : {"horizontal_m", "vertical_m", "heading_deg"}) {
      BatchCrossCheckRow row;
      row.a = d.value("a", std::string());
      row.b = d.value("b", std::string());
      row.sigma_form = cc.value("sigma", std::string("none"));
      row.statistic = name;
      row.rms_difference = number(d.value("outage_rms", json::object()), name);
      const json s = cc.value(name, json::object());
      row.rms_sigma = number(s, "rms_sigma");
      row.rms_normalized = number(s, "rms_normalized");
      row.max_normalized = number(s, "max_normalized");
      if (auto n = number(s, "epochs")) row.epochs = static_cast<int>(*n);
      r->cross_checks.push_back(std::move(row));
    }
  }
}

void readReal(const fs::path& dir, BatchRunRecord* r) {
  const json j = readJson(dir / "summary.json");
  Rows rows{r};
  const json estimators = j.value("estimators", json::array());
  for (const json& e : estimators) {
    const std::string est = e.value("estimator", std::string());
    const json cp = e.value("checkpoints", json::object());
    rows.add(est, est, "checkpoint", "points", "count", number(cp, "n"), "1");
    rows.add(est, est, "checkpoint", "horizontal_m", "rms", number(cp, "rms_h_m"), "m");
    rows.add(est, est, "checkpoint", "horizontal_m", "max_rms", number(cp, "rms_of_max_h_m"), "m");
    rows.add(est, est, "checkpoint", "vertical_m", "rms", number(cp, "rms_v_m"), "m");
    const json ref = e.value("reference", json::object());
    rows.add(est, est, "reference", "horizontal_m", "rms", number(ref, "outage_rms_h_m"), "m");
    rows.add(est, est, "reference", "horizontal_m", "max_rms", number(ref, "outage_max_rms_h_m"),
             "m");
    rows.add(est, est, "overall", "heading_deg", "rms", number(ref, "heading_rms_deg"), "deg");
  }
  if (const auto w = j.find("outage_windows_s"); w != j.end() && w->is_array())
    r->outage_count = static_cast<int>(w->size());
  r->reference = "GNSS check points; reference solution";
  std::string failed;
  const json failed_list = j.value("failed", json::array());
  for (const json& f : failed_list) failed += (failed.empty() ? "" : "; ") + f.get<std::string>();
  if (!failed.empty()) {
    r->ok = false;
    r->error = "failed estimator(s): " + failed;
  }
}

void readEvaluation(const fs::path& dir, const std::string& est, BatchRunRecord* r) {
  const json j = readJson(dir / "evaluation.json");
  Rows rows{r};
  const json err = j.value("err", json::object()), err_max = j.value("err_outage_max", json()),
             err_overall = j.value("err_overall", json()), diff = j.value("diff", json());
  for (const auto& [sol, v] : err.items()) rows.drift(est, sol, "outage", "rms", v);
  for (const auto& [sol, v] : err_max.items()) rows.drift(est, sol, "outage", "max_rms", v);
  for (const auto& [sol, v] : err_overall.items()) rows.drift(est, sol, "overall", "rms", v);
  for (const auto& [sol, v] : diff.items()) rows.drift(est, sol, "outage", "diff", v, true);
  if (auto n = number(j.value("outages", json::object()), "count")) r->outage_count = int(*n);
  r->reference = j.value("reference", std::string());
  const BatchPredictive p = readPredictive((dir / "evaluation.json").string());
  r->realizations = p.realizations;
  r->predictive = p.rows;
  readOutageDrift(dir / "outage_drift.csv", est, r);
}

void addEffects(const json& list, const char* kind, BatchRunRecord* r) {
  for (const json& e : list) {
    const std::string name = e.value("name", std::string()), sensor = e.value("sensor", "");
    const json unc = e.value("uncertainty", json::object());
    const json parameters = e.value("parameters", json::object());
    for (const auto& [key, v] : parameters.items()) {
      const json& u = unc.contains(key) ? unc[key] : json();
      auto num = [](const json& x) {
        return x.is_number() ? std::optional<double>(x.get<double>()) : std::nullopt;
      };
      if (v.is_array()) {
        for (std::size_t i = 0; i < v.size(); ++i)
          r->effects.push_back({kind, name, sensor, fmt::format("{}[{}]", key, i), num(v[i]),
                                u.is_array() && i < u.size() ? num(u[i]) : std::nullopt, ""});
      } else {
        r->effects.push_back(
            {kind, name, sensor, key, num(v), num(u), v.is_string() ? v.get<std::string>() : ""});
      }
    }
  }
}

void readDiagnose(const fs::path& dir, BatchRunRecord* r) {
  const json j = readJson(dir / "diagnosis.json");
  addEffects(j.value("effects", json::array()), "claimed", r);
  addEffects(j.value("ambiguous", json::array()), "ambiguous", r);
  addEffects(j.value("implausible", json::array()), "implausible", r);
  const json fit = j.value("fit", json::object());
  if (!fit.contains("err")) return;  // no --estimator: the finder only
  const std::string est = fit.value("estimator", std::string());
  Rows rows{r};
  const json err = fit["err"];
  for (const auto& [sol, v] : err.items()) rows.drift(est, sol, "outage", "rms", v);
  rows.drift(est, "SG2", "outage", "diff", fit.value("diff_before", json::object()), true);
  rows.drift(est, "SG3", "outage", "diff", fit.value("diff_after", json::object()), true);
  r->outage_count = static_cast<int>(fit.value("outages", json::array()).size());
}

}  // namespace

std::string solutionLabel(const std::string& label) {
  std::string s = label.rfind("IMU_", 0) == 0 ? label.substr(4) : label;
  if (s.rfind("SG#", 0) == 0) s.erase(2, 1);
  return s;
}

void readTaskOutputs(BatchCommand command, const std::string& out_dir,
                     const std::vector<std::string>& estimators, BatchRunRecord* record) {
  const fs::path dir(out_dir);
  const std::string est = estimators.empty() ? "none" : joined(estimators);
  switch (command) {
    case BatchCommand::kNavigate:
      return readNavigate(dir, est, record);
    case BatchCommand::kCompare:
      return readCompare(dir, record);
    case BatchCommand::kReal:
      return readReal(dir, record);
    case BatchCommand::kRealSg:
    case BatchCommand::kEvaluate:
      return readEvaluation(dir, est, record);
    case BatchCommand::kDiagnose:
      return readDiagnose(dir, record);
  }
}

BatchPredictive readPredictive(const std::string& path) {
  BatchPredictive out;
  if (!fs::exists(path)) return out;
  const json j = readJson(path);
  if (const auto k = j.find("realizations"); k != j.end() && k->is_number_integer())
    out.realizations = k->get<int>();
  const auto it = j.find("predictive");
  if (it == j.end() || !it->is_object()) return out;
  const json pct = j.value("real_percentile", json::object());
  const json ver = j.value("verdict", json::object());
  for (const auto& [solution, stats] : it->items()) {
    if (!stats.is_object()) continue;
    for (const auto& [statistic, v] : stats.items()) {
      if (!v.is_object()) continue;
      BatchPredictiveRow r;
      r.solution = solutionLabel(solution);
      r.statistic = statistic;
      r.p05 = number(v, "p05");
      r.p50 = number(v, "p50");
      r.p95 = number(v, "p95");
      r.mean = number(v, "mean");
      r.sd = number(v, "sd");
      // REAL's place sits beside "predictive", under the same solution and statistic keys.
      if (pct.contains(solution) && pct[solution].contains(statistic) &&
          pct[solution][statistic].is_number())
        r.real_percentile = pct[solution][statistic].get<double>();
      if (ver.contains(solution) && ver[solution].contains(statistic) &&
          ver[solution][statistic].is_string())
        r.verdict = ver[solution][statistic].get<std::string>();
      out.rows.push_back(std::move(r));
    }
  }
  return out;
}

}  // namespace graftnav
