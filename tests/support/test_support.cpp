#include "test_support.h"

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/sim/trajectory.h"

namespace graftnav::test {

std::string sourceDir() { return GRAFTNAV_SOURCE_DIR; }
std::string sharedDir() { return GRAFTNAV_SHARED_DIR; }
std::string graftnavBinary() { return GRAFTNAV_BINARY; }

bool sharedDataRequired() {
  const char* v = std::getenv("GRAFTNAV_REQUIRE_SHARED_DATA");
  return v != nullptr && std::string(v) == "1";
}

CommandOutput runGraftnav(const std::string& args, const std::string& shell_prefix) {
  const std::string cmd =
      "sh -c \"" + shell_prefix + " exec " + graftnavBinary() + " " + args + "\" 2>&1";
  CommandOutput out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.text.append(buf, n);
  const int status = pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return out;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

std::string makeTempDir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = tag;
  if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';
  // One folder per source tree: test runs of two checkouts at once (worktrees, CI jobs) must not
  // share a test's folder.
  const std::string tree = std::to_string(std::hash<std::string>{}(sourceDir()) % 1000000007u);
  const auto dir = std::filesystem::temp_directory_path() / ("graftnav_tests_" + tree) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x0, double step) {
  const Eigen::VectorXd y0 = f(x0);
  Eigen::MatrixXd J(y0.size(), x0.size());
  for (int i = 0; i < x0.size(); ++i) {
    Eigen::VectorXd xp = x0, xm = x0;
    xp[i] += step;
    xm[i] -= step;
    J.col(i) = (f(xp) - f(xm)) / (2.0 * step);
  }
  return J;
}

int expectDerivativesMatchCentralDifferences(const Trajectory& trj, double h, double tol_v_m_s,
                                             double tol_a_m_s2, double tol_omega_rad_s) {
  int checked = 0;
  for (double t = trj.startTime_s() + 2.0; t < trj.endTime_s() - 2.0; t += 7.3) {
    const TrajectoryPoint p = trj.at(t), pm = trj.at(t - h), pp = trj.at(t + h);
    const Eigen::Vector3d v_num = earth::nedFromGeodetic(pm.pos, pp.pos) / (2 * h);
    EXPECT_LT((v_num - p.v_n).norm(), tol_v_m_s) << t;
    EXPECT_LT(((pp.v_n - pm.v_n) / (2 * h) - p.a_n).norm(), tol_a_m_s2) << t;
    const Eigen::Matrix3d W = p.C_nb.transpose() * (pp.C_nb - pm.C_nb) / (2 * h);
    const Eigen::Vector3d w_num(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_LT((w_num - p.omega_nb_b).norm(), tol_omega_rad_s) << t;
    ++checked;
  }
  return checked;
}

}  // namespace graftnav::test
