// A bad value in a simulation config names the file, the line and the dotted key (the one YAML
// field helper, graftnav/io/yaml_fields.h).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "graftnav/sim/sim_config.h"
#include "test_support.h"

namespace graftnav {
namespace {

TEST(SimConfigErrors, BadValueNamesFileLineAndKey) {
  std::ifstream in(test::sourceDir() + "/configs/sim/concealed/time_offset_lever_arm.yaml");
  std::stringstream text;
  std::string line;
  int bad_line = 0;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto at = line.find("time_offset_s:");
    if (at != std::string::npos && bad_line == 0) {
      line = line.substr(0, at) + "time_offset_s: soon";
      bad_line = n;
    }
    const auto rel = line.find("../../imu/");  // the copy lives elsewhere: profiles by full path
    if (rel != std::string::npos) line.replace(rel, 10, test::sourceDir() + "/configs/imu/");
    text << line << "\n";
  }
  ASSERT_GT(bad_line, 0);
  const std::string dir = test::makeTempDir("sim_cfg_bad_value");
  const std::string path = dir + "/bad.yaml";
  std::ofstream(path) << text.str();
  try {
    loadSimConfig(path);
    FAIL() << "a non-number time offset was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bad.yaml:" + std::to_string(bad_line) + ":"), std::string::npos) << m;
    EXPECT_NE(m.find("'tested_imu.time_offset_s'"), std::string::npos) << m;
    EXPECT_NE(m.find("'soon'"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace graftnav
