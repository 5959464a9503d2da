// graftnav evaluate CASE_DIR --out OUT_DIR [--estimator ekf|rts|fgo] [--config FILE] ...
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <memory>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/nav/units.h"
#include "sg_evaluate.h"

namespace graftnav::app {

void registerEvaluate(CLI::App& app) {
  auto o = std::make_shared<SgEvaluateOptions>();
  auto len = std::make_shared<double>(-1), per = std::make_shared<double>(-1), st = std::make_shared<double>(-1);
  CLI::App* cmd = app.add_subcommand(
      "evaluate", "Calibrate, graft SG#1/SG#2, navigate SG1/SG2/REAL with GNSS outages, tabulate ERR and DIFF");
  cmd->add_option("case_dir", o->case_dir, "case directory")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", o->out_dir, "output directory")->required();
  cmd->add_option("--estimator", o->estimator, "ekf | rts | fgo | fgo-window")->capture_default_str();
  cmd->add_option("--run-config", o->config_path, "run config YAML (outages:, ekf:, fgo:, evaluation:)")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--run-config", &o->config_path);
  cmd->add_option("--outage-length", *len, "outage length (s), default 60");
  cmd->add_option("--outage-period", *per, "outage start-to-start period (s), default 180");
  cmd->add_option("--outage-start", *st, "first outage start after the first IMU epoch (s), default 300");
  cmd->add_option("--sol-ref", o->sol_ref, "auto (truth > reference solution > smoothed) | smooth")
      ->check(CLI::IsMember({"auto", "smooth"}))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "grafting seed")->capture_default_str();
  cmd->add_flag("--no-cross-axis", [o](int64_t) { o->use_cross_axis = false; },
                "SG#2 with per-axis fitting functions only, as in the seed");
  cmd->add_flag("--no-plots", [o](int64_t) { o->plots = false; }, "skip the matplotlib plots");
  cmd->add_option("--jobs", o->jobs, "solutions navigated in parallel (0: all cores)");
  cmd->callback([o, len, per, st]() {
    if (*len >= 0) o->outage_length_s = *len;
    if (*per >= 0) o->outage_period_s = *per;
    if (*st >= 0) o->outage_start_s = *st;
    const auto t0 = std::chrono::steady_clock::now();
    auto el = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    const SgEvaluationReport r =
        runSgEvaluation(*o, [&](const std::string& m) { fmt::print(stderr, "[{:6.1f} s] {}\n", el(), m); });
    fmt::print("{}: {} outages of {:.0f} s, estimator {}, SOL_REF {}\n", r.case_name, r.outages.size(),
               r.outage_length_s, r.estimator, r.reference);
    fmt::print("  {:<9} {:>13} {:>11} {:>10} {:>11} {:>13}\n", "", "horizontal_m", "vertical_m", "roll_deg",
               "pitch_deg", "heading_deg");
    for (const auto& s : r.solutions) {
      const auto a = asArray(s.evaluation.outage_rms);
      fmt::print("  ERR_{:<5} {:>13.3f} {:>11.3f} {:>10.4f} {:>11.4f} {:>13.4f}\n", s.label, a[0], a[1],
                 a[2] * units::kRadToDeg, a[3] * units::kRadToDeg, a[4] * units::kRadToDeg);
    }
    for (const auto& s : r.solutions) {
      if (s.label == "REAL") continue;
      if (auto d = r.diff(s.label)) {
        const auto a = asArray(*d);
        fmt::print("  DIFF_{:<4} {:>12.1f}% {:>10.1f}% {:>9.1f}% {:>10.1f}% {:>12.1f}%\n", s.label.substr(2),
                   100 * a[0], 100 * a[1], 100 * a[2], 100 * a[3], 100 * a[4]);
      }
    }
    fmt::print("  wrote evaluation.json, tables.md, evaluation.csv, outage_drift.csv, plots in {} ({:.1f} s)\n",
               o->out_dir, el());
  });
}

}  // namespace graftnav::app
