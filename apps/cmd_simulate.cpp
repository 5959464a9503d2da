// graftnav simulate --config FILE --out CASE_DIR [--seed N] [--track FILE.pos] [--ideal]
//                   [--common-random-numbers]
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "cli_vocabulary.h"
#include "commands.h"
#include "graftnav/sim/case_simulator.h"
#include "graftnav/sim/sim_config.h"

namespace graftnav::app {

void registerSimulate(CLI::App& app) {
  struct Args {
    std::string config, out, track;
    uint64_t seed = 0;
    bool ideal = false;
    bool common_random_numbers = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Simulate a whole case (field IMUs, GNSS, truth, lab sessions) from a sim config");
  cmd->add_option("--sim-config", args->config, "sim config YAML (configs/sim/*.yaml); required")
      ->check(CLI::ExistingFile);
  addDeprecatedOption(cmd, "--config", "--sim-config", &args->config);
  cmd->add_option("--out", args->out, "case directory to write")->required();
  auto* seed_opt = cmd->add_option("--seed", args->seed, "random seed (default: the config's)");
  cmd->add_option("--track", args->track, "use this .pos track instead of the config's trajectory")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--ideal", args->ideal, "every IMU error-free and GNSS noise-free");
  cmd->add_flag("--common-random-numbers", args->common_random_numbers,
                "lab noise = the field tested IMU's noise stream (sets lab.common_random_numbers)");
  cmd->callback([args, seed_opt]() {
    requireValue(args->config, "--sim-config");
    const auto t_start = std::chrono::steady_clock::now();
    std::vector<std::string> warnings;
    SimConfig cfg = loadSimConfig(args->config, &warnings);
    for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    if (seed_opt->count() > 0) cfg.seed = args->seed;
    if (!args->track.empty()) {
      SimTrackSource t = cfg.track.value_or(SimTrackSource{});
      t.path = args->track;
      if (!cfg.track) t.duration_s = 0.0;
      cfg.track = t;
      cfg.script.reset();
    }
    cfg.ideal = args->ideal;
    if (args->common_random_numbers) cfg.lab_common_random_numbers = true;
    auto elapsed = [&]() {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    };
    const CaseSimSummary s = simulateCase(cfg, args->out, [&](const std::string& m) {
      fmt::print(stderr, "[{:7.1f} s] {}\n", elapsed(), m);
    });
    fmt::print("simulated case '{}' in {} ({:.1f} s{})\n", cfg.name, args->out, elapsed(),
               cfg.ideal ? ", ideal" : "");
    fmt::print("  field {:.3f} .. {:.3f} s of week ({:.1f} s), path {:.0f} m\n", s.t_begin_s,
               s.t_end_s, s.t_end_s - s.t_begin_s, s.path_length_m);
    fmt::print("  IMU samples {}, truth epochs {}, GNSS fixes {}, lab files {}, seed {}\n",
               s.imu_samples, s.truth_epochs, s.gnss_fixes, s.lab_files, cfg.seed);
    if (cfg.track) {
      fmt::print(
          "  track fit: {} fixes used, {} rejected, {} stops, rms residual N/E/D "
          "{:.3f}/{:.3f}/{:.3f} m\n",
          s.track_fit.fixes_used, s.track_fit.fixes_rejected, s.track_fit.stops,
          s.track_fit.rms_residual_m[0], s.track_fit.rms_residual_m[1],
          s.track_fit.rms_residual_m[2]);
    }
  });
}

}  // namespace graftnav::app
