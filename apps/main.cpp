// graftnav: evaluate how well an IMU will navigate, by signal grafting (Niu et al. 2016).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <exception>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "commands.h"
#include "graftnav/io/provenance.h"

namespace {

// Blocks of 512 KiB and more are mapped on their own and unmapped when freed, so what a stage
// frees (a record, a library of regressor columns) goes back to the system before the next
// stage allocates. glibc's default threshold grows up to 32 MiB as large blocks are freed; the
// blocks below it then stay in the heap, fragmented: diagnose's peak RSS on a 57-min case was
// 411 MB against 313 MB of live heap (320 MB with a fixed threshold). The threshold is not
// lower because SuiteSparse's workspaces of a sliding-window solve with 21-state nodes are
// 128-512 KiB: mapped and unmapped on every solve, they cost fgo-window with vehicle aiding
// 8.7 s of system time (296 000 page faults) on a 25-min drive, against 0.5 s here. No peak RSS
// of docs/BENCHMARKS.md's commands on the 1-h case is more than 0.3 MB higher at 512 KiB.
void returnFreedMemoryToTheSystem() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 512 * 1024);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  returnFreedMemoryToTheSystem();
  CLI::App app{"graftnav: IMU evaluation by signal grafting (Niu et al., Sensors 2016)"};
  app.require_subcommand(1);
  graftnav::setCommandLine(argc, argv);
  app.set_version_flag("--version", graftnav::versionLine());
  graftnav::app::registerSimulate(app);
  graftnav::app::registerGraft(app);
  graftnav::app::registerEvaluate(app);
  graftnav::app::registerBatch(app);
  graftnav::app::registerCalibrate(app);
  graftnav::app::registerCompare(app);
  graftnav::app::registerNavigate(app);
  graftnav::app::registerDiagnose(app);
  graftnav::app::registerReal(app);
  graftnav::app::registerRealSg(app);
  graftnav::app::registerImport(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    fmt::print(stderr, "graftnav: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
