// graftnav evaluate CASE_DIR --out OUT_DIR [--estimator ekf|rts|fgo] [--config FILE] ...
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/case/sg_case_evaluation.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/nav/units.h"
#include "graftnav/sg/sg_report_files.h"
#include "sg_evaluate.h"

namespace graftnav::app {
namespace {

std::string cell(double v, int digits) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "n/a";
}

}  // namespace

void printEvaluationSummary(const SgEvaluationReport& r) {
  fmt::print("{}: {} outages of {:.0f} s{}, estimator {}, SOL_REF {}\n", r.case_name,
             r.outages.size(), r.outage_length_s,
             r.outage_shifts > 1 ? fmt::format(" at {} shifted schedules", r.outage_shifts) : "",
             r.estimator, r.reference);
  fmt::print("  ERR: mean over {} realizations [90 % interval of one realization]\n",
             r.realizations);
  static const std::array<const char*, 5> names{"horizontal_m", "vertical_m", "roll_deg",
                                                "pitch_deg", "heading_deg"};
  const SgSolutionErrors* real = r.find("REAL");
  for (int i = 0; i < 5; ++i) {
    const double u = i < 2 ? 1.0 : units::kRadToDeg;
    const int digits = i < 2 ? 3 : 4;
    std::string line = fmt::format("  {:<13}", names[i]);
    if (real) line += fmt::format(" REAL {:>9}", cell(asArray(real->err_rms)[i] * u, digits));
    for (const auto& s : r.solutions) {
      if (s.draws.empty()) continue;
      const PredictiveSummary& q = s.predictive.summary[i];
      line += fmt::format("  {} {} [{}, {}]", s.label, cell(q.mean * u, digits),
                          cell(q.p05 * u, digits), cell(q.p95 * u, digits));
      if (real && s.predictive.real_valid[i])
        line += fmt::format(" REAL@{:.0f}% {}", 100.0 * s.predictive.real_percentile[i],
                            verdictName(s.predictive.verdict[i]));
    }
    fmt::print("{}\n", line);
  }
  for (const auto& s : r.solutions) {
    if (s.label == "REAL") continue;
    if (auto d = r.diff(s.label)) {
      const auto a = asArray(*d);
      fmt::print("  DIFF_{} (of the mean) {:.1f}% {:.1f}% {:.1f}% {:.1f}% {:.1f}%\n",
                 s.label.substr(2), 100 * a[0], 100 * a[1], 100 * a[2], 100 * a[3], 100 * a[4]);
    }
  }
  for (const auto& l : readingLines(r)) fmt::print("  - {}\n", l);
}

void registerEvaluate(CLI::App& app) {
  auto o = std::make_shared<SgCaseEvaluationOptions>();
  auto plots = std::make_shared<bool>(true);
  auto sol_ref = std::make_shared<std::string>("auto");
  auto len = std::make_shared<std::optional<double>>(),
       per = std::make_shared<std::optional<double>>(),
       st = std::make_shared<std::optional<double>>();
  auto k = std::make_shared<std::optional<int>>(), shifts = std::make_shared<std::optional<int>>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate",
      "Calibrate, graft SG#1/SG#2, navigate SG#1/SG#2/REAL with GNSS outages, tabulate ERR and DIFF");
  cmd->add_option("case_dir", o->case_dir, "case directory")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", o->out_dir, "output directory")->required();
  cmd->add_option("--estimator", o->estimator, "the estimator of every solution")
      ->check(CLI::IsMember(estimatorTable().names()))
      ->capture_default_str();
  cmd->add_option("--run-config", o->run_config,
                  "run config YAML (outages:, ekf:, fgo:, evaluation:)")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &o->run_config);
  cmd->add_option("--outage-length", *len, "outage length (s), default 60");
  cmd->add_option("--outage-period", *per, "outage start-to-start period (s), default 180");
  cmd->add_option("--outage-start", *st,
                  "first outage start after the first IMU epoch (s), default 300");
  cmd->add_option("--sol-ref", *sol_ref, "auto (truth > reference solution > smoothed) | smooth")
      ->check(CLI::IsMember({"auto", "smooth"}))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "grafting seed (realization k draws from seed and k)")
      ->capture_default_str();
  cmd->add_option("--realizations", *k,
                  "grafted realizations per SG strategy, K (default 20, or grafting.realizations)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option(
         "--outage-shifts", *shifts,
         "repeat the outage schedule at N starts spread over one period and average ERR (default 1)")
      ->check(CLI::Range(1, 100000));
  cmd->add_flag(
      "--no-cross-axis", [o](int64_t) { o->use_cross_axis = false; },
      "SG#2 with per-axis fitting functions only, as in the seed");
  cmd->add_flag(
      "--no-plots", [plots](int64_t) { *plots = false; }, "skip the matplotlib plots");
  cmd->add_option("--jobs", o->jobs, "solutions navigated in parallel (0: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->callback([o, plots, sol_ref, len, per, st, k, shifts]() {
    o->outage_length_s = *len;
    o->outage_period_s = *per;
    o->outage_start_s = *st;
    o->realizations = *k;
    o->outage_shifts = *shifts;
    o->always_smooth_sol_ref = *sol_ref == "smooth";  // the flag's two values
    const auto t0 = std::chrono::steady_clock::now();
    auto el = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    const LogFn log = [&](const std::string& m) {
      fmt::print(stderr, "[{:6.1f} s] {}\n", el(), m);
    };
    const SgCaseEvaluation r = runSgCaseEvaluation(*o, estimatorTable(), log);
    writeSgOutputs(o->out_dir, r.report, *plots, log, !r.errors_csv_written);
    printEvaluationSummary(r.report);
    fmt::print(
        "  wrote evaluation.json, tables.md, evaluation.csv, predictive.csv, outage_drift.csv, plots in {} ({:.1f} s)\n",
        o->out_dir, el());
  });
}

}  // namespace graftnav::app
