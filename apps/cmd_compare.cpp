// graftnav compare CASE_DIR --out OUT_DIR [--estimator ekf,rts,fgo] [--imu ref|tested|FILE]
//                  [--outage-length S --outage-period S --outage-start S]
// Runs several estimators on one case and writes a side-by-side table of their outage errors
// (seed: RMS over outage epochs; peers: RMS of per-outage maxima) and of their differences from
// each other (the filter-versus-smoother cross-check), as Markdown and CSV, plus a 1 Hz error
// series for scripts/runtime/plot_compare.py.
//
// Estimators: every name of the shared table (apps/estimators.h: ekf, rts, fgo, fgo-window, ...)
// plus the graph variants fgo-noearth and fgo-window-noearth (Earth rotation off in the
// preintegration, for the Tang et al. comparison). --config takes the run config of `navigate`
// (its ekf:, fgo: and outages: sections).
#include <fmt/core.h>
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "graftnav/case/case_inputs.h"
#include "graftnav/case/problem.h"
#include "cli_vocabulary.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/io/provenance.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/run_config.h"
#include "script_locator.h"
#include "graftnav/eval/cross_check.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/nav/units.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/filters/rts_smoother.h"
#include "graftnav/graph/fgo_solver.h"

namespace graftnav::app {
namespace {

struct CompareArgs {
  std::string case_dir, out, imu;
  std::string estimators = "ekf,rts,fgo";
  std::string config, profile;
  OutageOverrides outage;  // over the run config's outages: (default 60 s every 180 s from 300 s)
  bool no_outages = false;
  bool lenient = false;
  bool no_plots = false;
};

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

NavSolution runNamed(const std::string& name, const EstimationProblem& p, const RunConfig& cfg) {
  const std::string suffix = "-noearth";
  if (name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    RunConfig c = cfg;
    c.fgo.earth_rotation = false;
    const std::string base = name.substr(0, name.size() - suffix.size());
    if (base != "fgo" && base != "fgo-window") {
      throw std::invalid_argument("compare: '" + name +
                                  "': -noearth applies to fgo and fgo-window");
    }
    NavSolution sol = estimatorTable().run(base, p, c);
    sol.estimator = name;
    return sol;
  }
  return estimatorTable().run(name, p, cfg);
}

// Every name must be in the table (or a -noearth variant of fgo / fgo-window), before any run.
void checkEstimatorNames(const std::vector<std::string>& names) {
  std::vector<std::string> known = estimatorTable().names();
  known.push_back("fgo-noearth");
  known.push_back("fgo-window-noearth");
  for (const auto& n : names)
    if (std::find(known.begin(), known.end(), n) == known.end())
      throw std::runtime_error("--estimators: unknown estimator '" + n + "'");
}

struct Row {
  std::string name;
  double seconds = 0.0;
  Evaluation eval;  // statistics only: the epochs are evaluated as a stream
  // The epochs of the 1 Hz error series: the first row's every >= 1 s, each other row's at or
  // after each of those times (the last when none is).
  std::vector<EpochError> series;
  int gnss_rejected = 0;
};

// Keeps the epochs of a row's 1 Hz error series as they are evaluated (Row::series); `grid`
// null for the first row, else the first row's series.
class SeriesSink final : public EpochErrorSink {
 public:
  SeriesSink(const std::vector<EpochError>* grid, std::vector<EpochError>* out)
      : grid_(grid), out_(out) {}
  void add(const EpochError& e) override {
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
  void commit() override {
    if (grid_ && last_)
      while (kept_.size() < grid_->size()) kept_.push_back(*last_);
    *out_ = std::move(kept_);
  }

 private:
  const std::vector<EpochError>* grid_;
  std::vector<EpochError>* out_;
  std::vector<EpochError> kept_;
  std::optional<EpochError> last_;
  double next_t_ = 0.0;
};

// One drift statistic as JSON (degrees for angles, null for a non-finite value).
nlohmann::json driftJson(const DriftStats& d) {
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {{"horizontal_m", num(d.horizontal_m)},
          {"vertical_m", num(d.vertical_m)},
          {"roll_deg", num(d.roll_rad * units::kRadToDeg)},
          {"pitch_deg", num(d.pitch_rad * units::kRadToDeg)},
          {"heading_deg", num(d.heading_rad * units::kRadToDeg)}};
}

// Formats table cells. A statistic that cannot be computed (no outage epoch, a zero denominator)
// is written as absent, "-" in Markdown and an empty CSV cell, and counted so that runCompare
// warns about it.
struct Cells {
  int absent = 0;
  std::string operator()(double v, const char* f, const char* absent_text) {
    if (std::isfinite(v)) return fmt::format(fmt::runtime(f), v);
    ++absent;
    return absent_text;
  }
  std::string driftMd(const DriftStats& d) {
    Cells& c = *this;
    return fmt::format("{} | {} | {} | {} | {}", c(d.horizontal_m, "{:.3f}", "-"),
                       c(d.vertical_m, "{:.3f}", "-"),
                       c(d.roll_rad * units::kRadToDeg, "{:.4f}", "-"),
                       c(d.pitch_rad * units::kRadToDeg, "{:.4f}", "-"),
                       c(d.heading_rad * units::kRadToDeg, "{:.4f}", "-"));
  }
  std::string driftCsv(const DriftStats& d) {
    Cells& c = *this;
    return fmt::format("{},{},{},{},{}", c(d.horizontal_m, "{:.6f}", ""),
                       c(d.vertical_m, "{:.6f}", ""),
                       c(d.roll_rad * units::kRadToDeg, "{:.6f}", ""),
                       c(d.pitch_rad * units::kRadToDeg, "{:.6f}", ""),
                       c(d.heading_rad * units::kRadToDeg, "{:.6f}", ""));
  }
};

// Pairwise differences inside outages: a evaluated against b as the reference.
struct Pair {
  std::string a, b;
  DriftStats rms, max_rms;
  CrossCheck cross;  // the difference weighed by its own sigma, when both carry sigmas
};

// ekf and rts are one forward filter and its smoother (var = P_a - P_b, with a the filter);
// every other pair is weighed by the sum of the variances, an upper bound.
Pair crossCheckPair(const std::string& name_a, const NavSolution& a, const std::string& name_b,
                    const NavSolution& b, const std::vector<TimeWindow>& outages) {
  const Evaluation e = evaluateSolution(a, b.states, outages);
  Pair q{name_a, name_b, e.outage_rms, e.outage_max_rms, {}};
  if (name_a == "rts" && name_b == "ekf") {
    q.cross = crossCheck(b, a, outages, DifferenceCovariance::kFilterSmoother);
  } else if (name_a == "ekf" && name_b == "rts") {
    q.cross = crossCheck(a, b, outages, DifferenceCovariance::kFilterSmoother);
  } else {
    q.cross = crossCheck(a, b, outages, DifferenceCovariance::kIndependent);
  }
  return q;
}

// One statistic of the cross-check; `scale` turns the difference's unit into the key's.
nlohmann::json crossCheckStatJson(const CrossCheckStat& s, double scale) {
  const auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
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

// The case, the run config and the outage schedule as `navigate` reads them
// (apps/case_loader.h), so both commands agree to the digit.
struct CompareInputs {
  RunConfig cfg;
  CaseInputs c;  // without its reference: read as a stream (reference)
  CaseReferenceFile reference;
  OutageScheduleConfig schedule;
  EstimationProblem p;
};

CompareInputs loadCompareInputs(const CompareArgs& a) {
  CompareInputs in;
  if (!a.config.empty()) {
    std::vector<std::string> warnings;
    in.cfg = loadRunConfig(a.config, &warnings);
    recordConfigFile(a.config);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  }
  CaseLoadOptions lo;
  lo.lenient = a.lenient;
  lo.load_reference = false;
  in.c = loadCaseInputs(a.case_dir, lo);
  in.reference = caseReferenceFile(in.c, a.lenient);
  in.c.reference_name = in.reference.path;
  in.c.reference_is_truth = in.reference.is_truth;
  const CaseInputs& c = in.c;
  for (const auto& w : c.warnings) fmt::print(stderr, "warning: {}\n", w);
  if (in.reference.path.empty())
    throw std::runtime_error(a.case_dir + ": compare needs truth.nav or a reference");
  OutageScheduleConfig& oc = in.schedule;
  oc = a.outage.appliedTo(in.cfg.outages);
  oc.enabled = oc.enabled && !a.no_outages;
  std::vector<std::string> notes;
  const ImuSelection imu = selectImu(c, a.imu, a.profile, a.lenient);
  if (!imu.read_summary.empty()) fmt::print(stderr, "warning: {}\n", imu.read_summary);
  if (!imu.profile_given) {
    throw std::runtime_error("no noise parameters for IMU '" + a.imu +
                             "' in case.yaml: pass --profile FILE");
  }
  for (const auto& w : checkGnssCoverage(c.gnss, c.paths().gnssPos(), imu.imu, false))
    fmt::print(stderr, "warning: {}\n", w);
  // makeProblem reads the reference's first epochs only (the week, the initial state).
  in.c.reference = readReferenceHead(in.reference, imu.imu.front().t_s - imu.imu.front().dt_s);
  in.p = makeProblem(c, imu, in.cfg, oc, &notes);
  in.c.reference = {};
  for (const auto& n : notes) fmt::print(stderr, "note: {}\n", n);
  const EstimationProblem& p = in.p;
  requireOutagesInsideData(oc, p.outages, p.imu.front().t_s - p.imu.front().dt_s, p.imu.back().t_s);
  // The reference read once here (its errors stop the run, its coverage is checked from counts);
  // each estimator's evaluation reads it again as a stream.
  NavStreamReader reader(in.reference.path, in.reference.policy);
  ReferenceCoverage coverage(p.outages);
  NavState state;
  while (reader.next(&state)) coverage.add(state.t_s);
  if (!in.reference.is_truth && !reader.report().summary().empty())
    fmt::print(stderr, "warning: {}\n", reader.report().summary());
  for (const auto& w : coverage.check(in.reference.path, p.imu))
    fmt::print(stderr, "warning: {}\n", w);
  return in;
}

std::string compareMarkdown(const CompareArgs& a, const CompareInputs& in,
                            const std::vector<Row>& rows, const std::vector<Pair>& pairs,
                            Cells& cell) {
  const EstimationProblem& p = in.p;
  std::ostringstream md;
  md << fmt::format(
      "# Estimator comparison: {}\n\nIMU: {} ({}), {} outages of {:.0f} s every "
      "{:.0f} s from {:.0f} s; errors against the {}.\n\n",
      a.case_dir, a.imu, p.imu_profile.name, p.outages.size(), in.schedule.length_s,
      in.schedule.period_s, in.schedule.start_s, in.c.reference_name);
  md << "## Outage errors, RMS over outage epochs (seed Tables 2-3)\n\n"
        "| estimator | horiz. (m) | vert. (m) | roll (deg) | pitch (deg) | heading (deg) | "
        "run (s) | GNSS rejected |\n|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    md << fmt::format("| {} | {} | {:.2f} | {} |\n", r.name, cell.driftMd(r.eval.outage_rms),
                      r.seconds, r.gnss_rejected);
  }
  md << "\n## Outage errors, RMS over outages of the per-outage maximum (peers)\n\n"
        "| estimator | horiz. (m) | vert. (m) | roll (deg) | pitch (deg) | heading (deg) |\n"
        "|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    md << fmt::format("| {} | {} |\n", r.name, cell.driftMd(r.eval.outage_max_rms));
  }
  if (!rows.empty()) {
    md << fmt::format(
        "\n## Ratios to {} (outage RMS)\n\n| estimator | horiz. | vert. | heading |\n"
        "|---|---|---|---|\n",
        rows.front().name);
    const DriftStats& b = rows.front().eval.outage_rms;
    for (const Row& r : rows) {
      const DriftStats& d = r.eval.outage_rms;
      md << fmt::format("| {} | {} | {} | {} |\n", r.name,
                        cell(d.horizontal_m / b.horizontal_m, "{:.3f}", "-"),
                        cell(d.vertical_m / b.vertical_m, "{:.3f}", "-"),
                        cell(d.heading_rad / b.heading_rad, "{:.3f}", "-"));
    }
  }
  md << "\n## Differences between estimators inside outages (RMS over outage epochs)\n\n"
        "| a - b | horiz. (m) | vert. (m) | roll (deg) | pitch (deg) | heading (deg) |\n"
        "|---|---|---|---|---|---|\n";
  for (const Pair& q : pairs)
    md << fmt::format("| {} - {} | {} |\n", q.a, q.b, cell.driftMd(q.rms));
  return md.str();
}

// CSV: one row per estimator and statistic, and per pair.
std::string compareCsv(const std::vector<Row>& rows, const std::vector<Pair>& pairs, Cells& cell) {
  std::ostringstream csv;
  csv << "kind,name,statistic,horizontal_m,vertical_m,roll_deg,pitch_deg,heading_deg,run_s,"
         "gnss_rejected\n";
  for (const Row& r : rows) {
    csv << fmt::format("error,{},outage_rms,{},{:.3f},{}\n", r.name,
                       cell.driftCsv(r.eval.outage_rms), r.seconds, r.gnss_rejected);
    csv << fmt::format("error,{},outage_max_rms,{},{:.3f},{}\n", r.name,
                       cell.driftCsv(r.eval.outage_max_rms), r.seconds, r.gnss_rejected);
    csv << fmt::format("error,{},overall_rms,{},{:.3f},{}\n", r.name,
                       cell.driftCsv(r.eval.overall_rms), r.seconds, r.gnss_rejected);
  }
  for (const Pair& q : pairs) {
    csv << fmt::format("difference,{}-{},outage_rms,{},,\n", q.a, q.b, cell.driftCsv(q.rms));
    csv << fmt::format("difference,{}-{},outage_max_rms,{},,\n", q.a, q.b,
                       cell.driftCsv(q.max_rms));
  }
  return csv.str();
}

// 1 Hz error series for the plot.
std::string errorSeriesCsv(const std::vector<Row>& rows, Cells& cell) {
  std::ostringstream ser;
  ser << "t_s";
  for (const Row& r : rows)
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
nlohmann::json compareJson(const CompareArgs& a, const EstimationProblem& p,
                           const std::vector<Row>& rows, const std::vector<Pair>& pairs) {
  nlohmann::json js = {{"case", a.case_dir},
                       {"imu", a.imu},
                       {"outage_count", p.outages.size()},
                       {"estimators", nlohmann::json::array()},
                       {"differences", nlohmann::json::array()},
                       {"provenance", provenanceJson()}};
  for (const Row& r : rows) {
    js["estimators"].push_back({{"name", r.name},
                                {"run_s", r.seconds},
                                {"gnss_rejected", r.gnss_rejected},
                                {"outage_rms", driftJson(r.eval.outage_rms)},
                                {"outage_max_rms", driftJson(r.eval.outage_max_rms)},
                                {"overall_rms", driftJson(r.eval.overall_rms)}});
  }
  for (const Pair& q : pairs) {
    js["differences"].push_back({{"a", q.a},
                                 {"b", q.b},
                                 {"outage_rms", driftJson(q.rms)},
                                 {"outage_max_rms", driftJson(q.max_rms)},
                                 {"cross_check", crossCheckJson(q.cross)}});
  }
  return js;
}

void runCompare(const CompareArgs& a) {
  if (!a.no_outages) a.outage.validate();
  const CompareInputs in = loadCompareInputs(a);
  const EstimationProblem& p = in.p;
  const std::vector<std::string> names = splitList(a.estimators);
  if (names.empty()) throw std::invalid_argument("compare: --estimators is empty");
  checkEstimatorNames(names);
  std::filesystem::create_directories(a.out);
  fmt::print(stderr, "compare: {} IMU samples, {} GNSS fixes, {} outages of {:.0f} s\n",
             p.imu.size(), p.gnss.size(), p.outages.size(), in.schedule.length_s);

  std::vector<Row> rows;
  std::vector<NavSolution> sols;
  for (const std::string& name : names) {
    const auto t0 = std::chrono::steady_clock::now();
    NavSolution sol = runNamed(name, p, in.cfg);
    checkGnssUsed(sol.gnss_used, false);  // throws before any file is written
    Row r;
    r.name = name;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::vector<EpochError>* grid = rows.empty() ? nullptr : &rows.front().series;
    r.eval = evaluateSolutionStreamed(
        sol, navFileSource(in.reference.path, in.reference.policy), p.outages, EvaluationOptions{},
        [&]() { return std::make_unique<SeriesSink>(grid, &r.series); });
    r.gnss_rejected = sol.gnss_rejected;
    fmt::print(stderr, "  {:<20s} {:7.2f} s  outage horiz RMS {:.3f} m, GNSS rejected {}\n", name,
               r.seconds, r.eval.outage_rms.horizontal_m, sol.gnss_rejected);
    rows.push_back(std::move(r));
    sols.push_back(std::move(sol));
  }
  std::vector<Pair> pairs;
  for (size_t i = 0; i < sols.size(); ++i) {
    for (size_t j = i + 1; j < sols.size(); ++j) {
      pairs.push_back(crossCheckPair(names[i], sols[i], names[j], sols[j], p.outages));
    }
  }

  Cells cell;
  const std::string md = compareMarkdown(a, in, rows, pairs, cell);
  std::ostringstream ow;
  ow << "start_s,end_s\n";
  for (const TimeWindow& w : p.outages) ow << fmt::format("{:.3f},{:.3f}\n", w.start_s, w.end_s);
  writeFileAtomically(a.out + "/compare.md", md);
  writeFileAtomically(a.out + "/compare.csv", compareCsv(rows, pairs, cell));
  writeFileAtomically(a.out + "/compare_errors.csv", errorSeriesCsv(rows, cell));
  writeFileAtomically(a.out + "/compare_outages.csv", ow.str());
  writeFileAtomically(a.out + "/compare.json", compareJson(a, p, rows, pairs).dump(2) + "\n");
  fmt::print("{}", md);
  if (cell.absent > 0)
    fmt::print(
        stderr,
        "warning: {} statistics could not be computed (no outage epoch or a zero denominator): "
        "written as '-' in compare.md and empty cells in the CSV files\n",
        cell.absent);
  fmt::print("\nwrote {0}/compare.md, {0}/compare.json, {0}/compare.csv, {0}/compare_errors.csv\n",
             a.out);
  if (a.no_plots) return;
  const std::string w = runPythonScript("plot_compare.py", {a.out});
  if (!w.empty()) fmt::print(stderr, "warning: {}\n", w);
}

}  // namespace

void registerCompare(CLI::App& app) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Run several estimators on one case; table and plot of outage errors and differences");
  cmd->add_option("case_dir", a->case_dir, "case directory")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--estimator", a->estimators,
                  "comma list of the estimator table's names, plus fgo-noearth, fgo-window-noearth")
      ->capture_default_str();
  addDeprecatedOption(cmd, "--estimators", "--estimator", &a->estimators);
  cmd->add_option(
      "--imu", a->imu,
      "ref | tested | FILE (an IMU text file, tested IMU's profile; default: ref, else the "
      "case's only IMU)");
  cmd->add_option("--outage-length", a->outage.length_s,
                  "outage length (s; default: the run config's, else 60)");
  cmd->add_option("--outage-period", a->outage.period_s,
                  "start-to-start spacing (s; default: the run config's, else 180)");
  cmd->add_option("--outage-start", a->outage.start_s,
                  "first outage start after the first IMU epoch (s; default: the run config's, "
                  "else 300)");
  cmd->add_flag("--no-outages", a->no_outages, "use every GNSS fix");
  cmd->add_option("--run-config", a->config,
                  "run config YAML (ekf:, fgo:, outages: sections; the outage flags override "
                  "its outages:)")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &a->config);
  cmd->add_option("--profile", a->profile, "IMU profile YAML (default: from case.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-plots", a->no_plots, "do not call scripts/runtime/plot_compare.py");
  cmd->add_flag("--lenient", a->lenient, "real-data read policies (repair/warn instead of error)");
  cmd->callback([a]() {
    a->imu = imuChoice(a->imu, a->case_dir);
    runCompare(*a);
  });
}

}  // namespace graftnav::app
