#pragma once
// Each subcommand lives in its own cmd_<name>.cpp and registers itself on the CLI11 app here.
// Library code throws; only these files print and choose exit codes.
#include <CLI/CLI.hpp>

namespace graftnav::app {

// Every register function adds one subcommand and its callback to `app`.
void registerSimulate(CLI::App& app);   // cmd_simulate.cpp
void registerGraft(CLI::App& app);      // cmd_graft.cpp
void registerEvaluate(CLI::App& app);   // cmd_evaluate.cpp
void registerBatch(CLI::App& app);      // cmd_batch.cpp
void registerCalibrate(CLI::App& app);  // cmd_calibrate.cpp
void registerCompare(CLI::App& app);    // cmd_compare.cpp
void registerNavigate(CLI::App& app);   // cmd_navigate.cpp
void registerDiagnose(CLI::App& app);   // cmd_diagnose.cpp
void registerReal(CLI::App& app);       // cmd_real.cpp
void registerRealSg(CLI::App& app);     // cmd_real_sg.cpp
void registerImport(CLI::App& app);     // cmd_import.cpp (kf-gins, ob-gins)

}  // namespace graftnav::app
