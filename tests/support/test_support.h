#pragma once
// Helpers shared by every test executable.
#include <Eigen/Core>
#include <functional>
#include <string>

namespace graftnav::test {

// Root of the source tree and of ../shared (compiled in by CMake).
std::string sourceDir();
std::string sharedDir();
// Path of the built graftnav executable.
std::string graftnavBinary();
// A fresh, empty temporary directory unique to the calling test.
std::string makeTempDir(const std::string& tag);

// Central-difference Jacobian of f at x0 (the one numeric-Jacobian helper of the test suites).
Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x0, double step = 1e-6);

}  // namespace graftnav::test
