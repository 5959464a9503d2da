// `graftnav compare` end to end on the bundled MEMS sample: the table and CSV are written, and the
// batch smoother agrees with the RTS smoother inside the outages while the causal window does not.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "test_support.h"

namespace graftnav {
namespace {

TEST(CompareApp, WritesTableAndSmoothersAgree) {
  const std::string bin = test::graftnavBinary();
  if (!std::filesystem::exists(bin)) GTEST_SKIP() << "graftnav binary not built: " << bin;
  const std::string out = test::makeTempDir("compare_app");
  const std::string cmd = bin + " compare " + test::sourceDir() +
                          "/data/sample_mems --imu tested --out " + out +
                          " --estimators rts,fgo,fgo-window --outage-start 120 --outage-period 150"
                          " > " +
                          out + "/stdout.txt 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ASSERT_TRUE(std::filesystem::exists(out + "/compare.md"));
  std::ifstream csv(out + "/compare.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("kind,name,statistic,horizontal_m", 0), 0u) << line;
  std::map<std::string, double> outage_h;  // estimator -> outage RMS horizontal (m)
  int differences = 0;
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::string kind, name, stat, h;
    std::getline(ss, kind, ',');
    std::getline(ss, name, ',');
    std::getline(ss, stat, ',');
    std::getline(ss, h, ',');
    if (kind == "error" && stat == "outage_rms") outage_h[name] = std::stod(h);
    if (kind == "difference" && stat == "outage_rms") ++differences;
  }
  ASSERT_EQ(outage_h.size(), 3u);
  EXPECT_EQ(differences, 3);  // every pair
  EXPECT_LT(outage_h["fgo"], 1.3 * outage_h["rts"]);
  EXPECT_LT(outage_h["fgo"], 0.5 * outage_h["fgo-window"]);
}

}  // namespace
}  // namespace graftnav
