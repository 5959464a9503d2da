#pragma once
// Helpers shared by every test executable.
#include <Eigen/Core>
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
// A fresh, empty temporary directory unique to the calling test.
std::string makeTempDir(const std::string& tag);

// Central-difference Jacobian of f at x0 (the one numeric-Jacobian helper of the test suites).
Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x0, double step = 1e-6);

// Checks a trajectory's analytic v_n, a_n and omega_nb_b against central differences of its own
// position, v_n and C_nb (step h) every 7.3 s from 2 s after its start to 2 s before its end,
// with a gtest expectation per point and quantity; returns the number of points checked.
int expectDerivativesMatchCentralDifferences(const Trajectory& trj, double h, double tol_v_m_s,
                                             double tol_a_m_s2, double tol_omega_rad_s);

}  // namespace graftnav::test
