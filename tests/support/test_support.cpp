#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace graftnav::test {

std::string sourceDir() { return GRAFTNAV_SOURCE_DIR; }
std::string sharedDir() { return GRAFTNAV_SHARED_DIR; }
std::string graftnavBinary() { return GRAFTNAV_BINARY; }

std::string makeTempDir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = tag;
  if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';
  const auto dir = std::filesystem::temp_directory_path() / "graftnav_tests" / name;
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

}  // namespace graftnav::test
