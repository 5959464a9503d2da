// graftnav import kf-gins CONFIG.yaml --out CASE [--reference FILE.nav] [--copy] [--min-gap S]
// graftnav import ob-gins CONFIG.yaml --out CASE [...]
// A case folder from a KF-GINS or OB_GINS set-up (core/io peer_config.h, peer_import.h); then
// `graftnav navigate CASE --out DIR` runs the peer's set-up. What was assumed or not converted is
// printed and kept in CASE/notes.md.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "commands.h"
#include "graftnav/io/peer_import.h"

namespace graftnav::app {
namespace {

struct ImportArgs {
  std::string config, out;
  ImportOptions options;
};

void runImport(PeerFormat format, const ImportArgs& a) {
  std::vector<std::string> warnings;
  const PeerSetup setup = loadPeerConfig(format, a.config, &warnings);
  for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
  const ImportResult r = importPeerSetup(setup, a.out, a.options);
  fmt::print("imported {} set-up {} -> {}\n", peerFormatName(format), a.config, r.case_dir);
  fmt::print("  IMU {} at {} Hz, GNSS {}\n", setup.imu_path, setup.imu_rate_hz, setup.gnss_path);
  fmt::print("  {} outage windows", r.outages.size());
  for (const auto& w : r.outages) fmt::print(" [{:.3f}, {:.3f}]", w.start_s, w.end_s);
  fmt::print("\n  assumed or not converted (kept in {}/notes.md):\n", r.case_dir);
  for (const auto& n : r.notes) fmt::print("  - {}\n", n);
  fmt::print("  next: graftnav navigate {} --out OUT_DIR\n", r.case_dir);
}

void addPeer(CLI::App* parent, PeerFormat format, const std::string& description) {
  auto a = std::make_shared<ImportArgs>();
  CLI::App* cmd = parent->add_subcommand(peerFormatName(format), description);
  cmd->add_option("config", a->config, "the peer's yaml")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", a->out, "case directory to write")->required();
  cmd->add_option("--reference", a->options.reference_path,
                  "reference solution (.nav) to evaluate against (field/reference.nav)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--copy", a->options.copy_files, "copy the data files instead of linking them");
  cmd->add_option("--min-gap", a->options.min_gap_s, "shortest GNSS gap taken as an outage (s)")
      ->capture_default_str();
  cmd->add_option("--gap-factor", a->options.gap_factor,
                  "a gap is an outage above this many median GNSS intervals")
      ->capture_default_str();
  cmd->add_option("--name", a->options.case_name, "case name (default: the yaml's file stem)");
  cmd->callback([a, format]() { runImport(format, *a); });
}

}  // namespace

void registerImport(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("import", "a case folder from a KF-GINS or OB_GINS set-up");
  cmd->require_subcommand(1);
  addPeer(cmd, PeerFormat::kKfGins, "from a KF-GINS yaml (imupath, gnsspath, imunoise, ...)");
  addPeer(cmd, PeerFormat::kObGins, "from an OB_GINS yaml (imufile, gnssfile, imumodel, ...)");
}

}  // namespace graftnav::app
