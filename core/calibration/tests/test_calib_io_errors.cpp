// A bad value in a calibration file names the file, the line and the dotted key (the one YAML
// field helper, graftnav/io/yaml_fields.h).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "graftnav/calibration/calibration_io.h"
#include "test_support.h"

namespace graftnav {
namespace {

TEST(CalibIoErrors, BadValueNamesFileLineAndKey) {
  const std::string path = test::makeTempDir("calib_io_bad_value") + "/calibration.yaml";
  std::ofstream(path) << "case: x\n"
                         "accel: {M: [[1,0,0],[0,1,0],[0,0,1]], bias: [0,0,0]}\n"
                         "gyro:\n"
                         "  M: [[1,0,0],[0,1,0],[0,0,1]]\n"
                         "  bias: [0,0,0]\n"
                         "  fit:\n"
                         "    x: {coeffs: [0, 1]}\n"
                         "    y: {coeffs: [0, 1], n_points: twelve}\n"
                         "    z: {coeffs: [0, 1]}\n";
  try {
    readCalibrationYaml(path);
    FAIL() << "a non-integer n_points was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path + ":8:"), std::string::npos) << m;
    EXPECT_NE(m.find("'gyro.fit.y.n_points'"), std::string::npos) << m;
    EXPECT_NE(m.find("'twelve'"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace graftnav
