#pragma once
// Helpers shared by every test executable.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>

namespace graftnav {
class Trajectory;
}

namespace graftnav::test {

// Root of the source tree and of ../shared (compiled in by CMake).
std::string sourceDir();
std::string sharedDir();
// Path of the built graftnav executable.
std::string graftnavBinary();
// What a run of the graftnav command printed (stdout and stderr together) and its exit code
// (128 + the signal's number when a signal ended it).
struct CommandOutput {
  int exit_code = -1;
  std::string text;
};

// Runs `graftnav ARGS` through sh, `shell_prefix` first (e.g. a ulimit), and captures its output
// through a pipe, so a file-size limit on the command does not hit its own log.
CommandOutput runGraftnav(const std::string& args, const std::string& shell_prefix = "");

// The message of the exception f throws, or "(no error)" when it returns.
std::string errorOf(const std::function<void()>& f);

// A fresh, empty temporary directory unique to the calling test.
std::string makeTempDir(const std::string& tag);

// True when missing ../shared data must fail a test rather than skip it: the environment variable
// GRAFTNAV_REQUIRE_SHARED_DATA is set to 1 (`.ci/run` sets it).
bool sharedDataRequired();

// Central-difference Jacobian of f at x0 (the one numeric-Jacobian helper of the test suites).
Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x0, double step = 1e-6);

// Checks a trajectory's analytic v_n, a_n and omega_nb_b against central differences of its own
// position, v_n and C_nb (step h) every 7.3 s from 2 s after its start to 2 s before its end,
// with a gtest expectation per point and quantity; returns the number of points checked.
int expectDerivativesMatchCentralDifferences(const Trajectory& trj, double h, double tol_v_m_s,
                                             double tol_a_m_s2, double tol_omega_rad_s);

}  // namespace graftnav::test

// Skips the calling test when `path` (under ../shared) does not exist, or fails it when
// sharedDataRequired(): CI must not pass by skipping what it was meant to check.
#define GRAFTNAV_REQUIRE_SHARED_PATH(path)                         \
  do {                                                             \
    const std::string graftnav_path_ = (path);                     \
    if (!std::filesystem::exists(graftnav_path_)) {                \
      if (::graftnav::test::sharedDataRequired()) {                \
        FAIL() << "shared data missing: " << graftnav_path_        \
               << " (GRAFTNAV_REQUIRE_SHARED_DATA=1)";             \
      }                                                            \
      GTEST_SKIP() << "shared data not found: " << graftnav_path_; \
    }                                                              \
  } while (0)
