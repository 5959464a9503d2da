// A bad value in a run config names the file, the line and the dotted key
// (the one YAML field helper, graftnav/io/yaml_fields.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "test_support.h"

namespace graftnav {
namespace {

TEST(RunConfigErrors, BadValueNamesFileLineAndKey) {
  const std::string dir = test::makeTempDir("run_config_bad_value");
  std::ofstream(dir + "/run.yaml") << "outages:\n  length_s: 60\ngrafting:\n  realizations: many\n";
  const std::string log = dir + "/log.txt";
  const std::string cmd = test::graftnavBinary() + " evaluate " + test::sourceDir() +
                          "/data/sample_mems --out " + dir + "/out --no-plots --run-config " + dir +
                          "/run.yaml > " + log + " 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::stringstream out;
  out << std::ifstream(log).rdbuf();
  EXPECT_NE(out.str().find("run.yaml:4:"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("'grafting.realizations'"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("'many'"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace graftnav
