// graftnav: evaluate how well an IMU will navigate, by signal grafting (Niu et al. 2016).
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <exception>

#include "commands.h"
#include "provenance.h"

int main(int argc, char** argv) {
  CLI::App app{"graftnav: IMU evaluation by signal grafting (Niu et al., Sensors 2016)"};
  app.require_subcommand(1);
  graftnav::app::setCommandLine(argc, argv);
  app.set_version_flag("--version", graftnav::app::versionLine());
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
