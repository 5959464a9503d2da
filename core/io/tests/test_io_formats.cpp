// Round trips and strict-mode errors of the IMU, GNSS and navigation text formats.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/nav/units.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

void writeText(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

// Runs fn, expects a std::runtime_error whose message contains every fragment.
template <typename Fn>
std::string expectError(Fn fn, const std::vector<std::string>& fragments) {
  try {
    fn();
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_THAT(msg, HasSubstr(f));
    return msg;
  }
  ADD_FAILURE() << "no std::runtime_error thrown";
  return {};
}

ImuSeries randomImu(int n, double rate_hz, bool with_temperature, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  ImuSeries imu(n);
  for (int k = 0; k < n; ++k) {
    ImuSample& s = imu[k];
    s.t_s = 456300.0 + (k + 1) / rate_hz;
    s.dt_s = 1.0 / rate_hz;
    // Values over many decades, signs and tiny magnitudes.
    s.dtheta_rad = Eigen::Vector3d(g(rng), g(rng), g(rng)) * 1e-4 * std::pow(10.0, (k % 7) - 3);
    s.dvel_m_s = Eigen::Vector3d(g(rng), g(rng), g(rng)) * 0.05;
    if (with_temperature) s.temperature_degC = 25.0 + g(rng);
  }
  return imu;
}

TEST(IoImu, RoundTripIsExact) {
  const std::string dir = test::makeTempDir("io");
  for (bool temp : {false, true}) {
    const ImuSeries imu = randomImu(2000, 200.0, temp, 11);
    const std::string path = dir + (temp ? "/imu_temp.txt" : "/imu.txt");
    writeImu(path, imu);
    ImuReadOptions opt;
    opt.nominal_rate_hz = 200.0;
    ReadReport report;
    const ImuSeries back = readImu(path, opt, &report);
    ASSERT_EQ(back.size(), imu.size());
    EXPECT_TRUE(report.clean()) << report.summary();
    EXPECT_EQ(report.records_kept, 2000);
    for (std::size_t k = 0; k < imu.size(); ++k) {
      EXPECT_NEAR(back[k].t_s, imu[k].t_s, 1e-9);
      EXPECT_NEAR(back[k].dt_s, 1.0 / 200.0, 2e-9);
      for (int i = 0; i < 3; ++i) {
        EXPECT_LE(std::fabs(back[k].dtheta_rad[i] - imu[k].dtheta_rad[i]),
                  1e-15 * std::fabs(imu[k].dtheta_rad[i]));
        EXPECT_LE(std::fabs(back[k].dvel_m_s[i] - imu[k].dvel_m_s[i]),
                  1e-15 * std::fabs(imu[k].dvel_m_s[i]));
      }
      EXPECT_EQ(back[k].hasTemperature(), temp);
      if (temp) {
        EXPECT_NEAR(back[k].temperature_degC, imu[k].temperature_degC, 5e-5);
      }
    }
  }
}

TEST(IoImu, FirstIntervalFromRateOrSecondInterval) {
  const std::string path = test::makeTempDir("io") + "/imu.txt";
  writeText(path,
            "100.000 0 0 0 0 0 0\n"
            "100.010 1e-3 0 0 0 0 9.8e-2\n"
            "100.020 0 0 0 0 0 0\n");
  ImuReadOptions with_rate;
  with_rate.nominal_rate_hz = 100.0;
  EXPECT_DOUBLE_EQ(readImu(path, with_rate)[0].dt_s, 0.01);
  const ImuSeries imu = readImu(path);
  EXPECT_NEAR(imu[0].dt_s, 100.010 - 100.000, 1e-12);
  EXPECT_NEAR(imu[2].dt_s, 100.020 - 100.010, 1e-12);
  EXPECT_DOUBLE_EQ(imu[1].dtheta_rad.x(), 1e-3);
  EXPECT_DOUBLE_EQ(imu[1].dvel_m_s.z(), 9.8e-2);
  EXPECT_FALSE(imu[1].hasTemperature());
}

TEST(IoImu, BadInputNamesFileLineAndValue) {
  const std::string dir = test::makeTempDir("io");
  const std::string good1 = "456300.000 0 0 0 0 0 0\n";
  const std::string good2 = "456300.005 0 0 0 0 0 0\n";
  struct Case {
    std::string name, text;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {"malformed", good1 + "456300.005 0 0 abc 0 0 0\n", {":2:", "'abc'", "column 4"}},
      {"few_columns",
       good1 + good2 + "456300.010 0 0 0 0 0\n",
       {":3:", "6 columns", "expected 7 or 8"}},
      {"many_columns", good1 + "456300.005 0 0 0 0 0 0 25 1\n", {":2:", "9 columns"}},
      {"mixed_temp", good1 + "456300.005 0 0 0 0 0 0 25\n", {":2:", "8 columns", "temperature"}},
      {"nan", good1 + good2 + "456300.010 0 nan 0 0 0 0\n", {":3:", "'nan'", "dtheta_y"}},
      {"inf", good1 + "456300.005 0 0 0 0 -inf 0\n", {":2:", "'-inf'"}},
      {"backwards",
       good1 + "456300.010 0 0 0 0 0 0\n456300.005 0 0 0 0 0 0\n",
       {":3:", "time 456300.005 is not after previous 456300.010"}},
      {"duplicate", good1 + good2 + good2, {":3:", "456300.005 is not after previous 456300.005"}},
      {"gap", good1 + good2 + "456300.020 0 0 0 0 0 0\n", {":3:", "gap", "3.000 x nominal"}},
      {"uneven", good1 + good2 + "456300.0062 0 0 0 0 0 0\n", {":3:", "uneven", "0.240 x nominal"}},
      {"empty", "\n\n", {"no IMU samples"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".txt";
    writeText(path, c.text);
    ImuReadOptions opt;
    opt.nominal_rate_hz = 200.0;
    auto frags = c.fragments;
    frags.push_back(path);
    expectError([&] { readImu(path, opt); }, frags);
  }
  expectError([&] { readImu(dir + "/does_not_exist.txt"); },
              {dir + "/does_not_exist.txt", "cannot open"});
}

TEST(IoImu, WriterRejectsBadSeriesAndLeavesNoFile) {
  const std::string dir = test::makeTempDir("io");
  ImuSeries imu = randomImu(10, 100.0, false, 3);
  imu[5].dvel_m_s.y() = std::nan("");
  EXPECT_THROW(writeImu(dir + "/bad.txt", imu), std::invalid_argument);
  imu = randomImu(10, 100.0, false, 3);
  imu[6].t_s = imu[5].t_s;
  EXPECT_THROW(writeImu(dir + "/bad.txt", imu), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.txt"));
  // No temporary files left behind either.
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  EXPECT_THROW(writeImu(dir + "/no_such_dir/x.txt", randomImu(3, 100.0, false, 1)),
               std::runtime_error);
}

GnssSeries randomGnss(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  GnssSeries fixes(n);
  for (int k = 0; k < n; ++k) {
    GnssFix& f = fixes[k];
    f.t_s = 456300.0 + k;
    f.pos = Geodetic{(30.0 + 0.01 * u(rng)) * units::kDegToRad,
                     (114.0 + 0.01 * u(rng)) * units::kDegToRad, 20.0 + u(rng)};
    f.std_ned_m = Eigen::Vector3d(0.02 + 0.01 * std::fabs(u(rng)), 0.021, 0.05);
    f.fix_type = (k % 3 == 0) ? 4 : 1;
    f.num_sv = 10 + k % 20;
  }
  return fixes;
}

TEST(IoGnss, PosAndFixTypeRoundTrip) {
  const std::string dir = test::makeTempDir("io");
  const GnssSeries fixes = randomGnss(300, 5);
  writeGnssPos(dir + "/gnss.pos", fixes);
  writeGnssFixTypes(dir + "/gnss_fixtype.txt", fixes);
  std::vector<ReadReport> reports;
  const GnssSeries back = readGnss(dir + "/gnss.pos", dir + "/gnss_fixtype.txt", {}, &reports);
  ASSERT_EQ(back.size(), fixes.size());
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_TRUE(reports[0].clean() && reports[1].clean());
  const double kLatLonTol = 0.6e-10 * units::kDegToRad;  // 10 decimals of a degree
  for (std::size_t k = 0; k < fixes.size(); ++k) {
    EXPECT_NEAR(back[k].t_s, fixes[k].t_s, 1e-6);
    EXPECT_NEAR(back[k].pos.lat_rad, fixes[k].pos.lat_rad, kLatLonTol);
    EXPECT_NEAR(back[k].pos.lon_rad, fixes[k].pos.lon_rad, kLatLonTol);
    EXPECT_NEAR(back[k].pos.h_m, fixes[k].pos.h_m, 0.6e-4);
    EXPECT_TRUE(back[k].std_ned_m.isApprox(fixes[k].std_ned_m, 1e-2));
    EXPECT_EQ(back[k].fix_type, fixes[k].fix_type);
    EXPECT_EQ(back[k].num_sv, fixes[k].num_sv);
  }
  // Without the fix type file the type is unknown (0).
  EXPECT_EQ(readGnssPos(dir + "/gnss.pos")[0].fix_type, 0);
}

TEST(IoGnss, BadInputNamesFileLineAndValue) {
  const std::string dir = test::makeTempDir("io");
  const std::string l1 = "456300.0 30.1 114.2 20.0 0.02 0.02 0.05\n";
  const std::string l2 = "456301.0 30.1 114.2 20.0 0.02 0.02 0.05\n";
  struct Case {
    std::string name, text;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {"malformed", l1 + "456301.0 30.1 114.2x 20.0 0.02 0.02 0.05\n", {":2:", "'114.2x'"}},
      {"columns", l1 + "456301.0 30.1 114.2 20.0 0.02 0.02\n", {":2:", "6 columns", "expected 7"}},
      {"nan", l1 + "456301.0 30.1 114.2 NaN 0.02 0.02 0.05\n", {":2:", "height", "'NaN'"}},
      {"backwards",
       l1 + l2 + "456300.5 30.1 114.2 20.0 0.02 0.02 0.05\n",
       {":3:", "time 456300.5 is not after previous 456301.0"}},
      {"zero_std", l1 + "456301.0 30.1 114.2 20.0 0.02 0.00 0.05\n", {":2:", "std_east", "'0.00'"}},
      {"negative_std", l1 + "456301.0 30.1 114.2 20.0 -0.02 0.01 0.05\n", {":2:", "negative"}},
      {"latitude", l1 + "456301.0 95.1 114.2 20.0 0.02 0.01 0.05\n", {":2:", "latitude 95.1"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".pos";
    writeText(path, c.text);
    auto frags = c.fragments;
    frags.push_back(path);
    expectError([&] { readGnssPos(path); }, frags);
  }
  expectError([&] { readGnssPos(dir + "/missing.pos"); }, {dir + "/missing.pos", "cannot open"});

  // Fix type file: a non-integer type, and an epoch with no .pos epoch.
  writeText(dir + "/gnss.pos", l1 + l2);
  writeText(dir + "/ft_bad.txt", "456300.0 4.5 12\n");
  expectError([&] { readGnssFixTypes(dir + "/ft_bad.txt"); },
              {dir + "/ft_bad.txt:1:", "fix_type", "'4.5'"});
  writeText(dir + "/ft_extra.txt", "456300.0 4 12\n456300.5 4 12\n456301.0 1 9\n");
  expectError([&] { readGnss(dir + "/gnss.pos", dir + "/ft_extra.txt"); },
              {dir + "/ft_extra.txt:2:", "456300.500000 has no .pos epoch"});
}

NavSeries randomNav(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  NavSeries nav(n);
  for (int k = 0; k < n; ++k) {
    NavState& s = nav[k];
    s.gnss_week = 2100;
    s.t_s = 604799.0 + 0.01 * k;  // crosses the week end: week stays as given
    if (s.t_s >= 604800.0) {
      s.t_s -= 604800.0;
      s.gnss_week = 2101;
    }
    s.pos = Geodetic{(30.0 + u(rng)) * units::kDegToRad, (114.0 + u(rng)) * units::kDegToRad,
                     20.0 + 10.0 * u(rng)};
    s.v_n = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 20.0;
    s.q_nb = quatFromEuler(Eigen::Vector3d(M_PI * u(rng), 0.49 * M_PI * u(rng), M_PI * u(rng)));
  }
  return nav;
}

TEST(IoNav, RoundTripAndEulerConversion) {
  const std::string dir = test::makeTempDir("io");
  const NavSeries nav = randomNav(500, 9);
  writeNav(dir + "/truth.nav", nav);
  const NavSeries back = readNav(dir + "/truth.nav");
  ASSERT_EQ(back.size(), nav.size());
  for (std::size_t k = 0; k < nav.size(); ++k) {
    EXPECT_EQ(back[k].gnss_week, nav[k].gnss_week);
    EXPECT_NEAR(back[k].t_s, nav[k].t_s, 1e-9);
    EXPECT_NEAR(back[k].pos.lat_rad, nav[k].pos.lat_rad, 1e-11 * units::kDegToRad);
    EXPECT_NEAR(back[k].pos.lon_rad, nav[k].pos.lon_rad, 1e-11 * units::kDegToRad);
    EXPECT_NEAR(back[k].pos.h_m, nav[k].pos.h_m, 1e-6);
    EXPECT_LT((back[k].v_n - nav[k].v_n).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT(back[k].q_nb.angularDistance(nav[k].q_nb), 1e-10);
  }
  // Known answer: a line in degrees gives the rotation.h quaternion and the NED velocity.
  writeText(
      dir + "/one.nav",
      "2204 203294.532 40.2024085 116.2256281 50.0026 -0.088 -0.1 0.093 -5.545 -3.366 348.342\n");
  const NavState s = readNav(dir + "/one.nav").front();
  EXPECT_EQ(s.gnss_week, 2204);
  EXPECT_DOUBLE_EQ(s.t_s, 203294.532);
  EXPECT_NEAR(s.pos.lat_rad, 40.2024085 * units::kDegToRad, 1e-15);
  EXPECT_DOUBLE_EQ(s.v_n.z(), 0.093);
  const Eigen::Vector3d e = eulerFromQuat(s.q_nb) * units::kRadToDeg;
  EXPECT_NEAR(e.x(), -5.545, 1e-10);
  EXPECT_NEAR(e.y(), -3.366, 1e-10);
  EXPECT_NEAR(e.z(), 348.342 - 360.0, 1e-10);
  // Yaw is written in [0, 360).
  writeNav(dir + "/one_back.nav", {s});
  std::ifstream f(dir + "/one_back.nav");
  std::string line;
  std::getline(f, line);
  EXPECT_THAT(line, HasSubstr(" 348.342000000"));
}

TEST(IoNav, BadInputNamesFileLineAndValue) {
  const std::string dir = test::makeTempDir("io");
  const std::string l1 = "2100 456300.0 30.1 114.2 20.0 0 0 0 0 0 90\n";
  const std::string l2 = "2100 456300.1 30.1 114.2 20.0 0 0 0 0 0 90\n";
  struct Case {
    std::string name, text;
    std::vector<std::string> fragments;
  };
  const std::vector<Case> cases = {
      {"malformed", l1 + "2100 456300.1 30.1 114.2 20.0 0 0 0 0 - 90\n", {":2:", "'-'"}},
      {"columns",
       l1 + "456300.1 30.1 114.2 20.0 0 0 0 0 0 90\n",
       {":2:", "10 columns", "expected 11"}},
      {"week", l1 + "2100.5 456300.1 30.1 114.2 20.0 0 0 0 0 0 90\n", {":2:", "week", "'2100.5'"}},
      {"inf", l1 + "2100 456300.1 30.1 114.2 20.0 0 inf 0 0 0 90\n", {":2:", "v_east", "'inf'"}},
      {"backwards", l1 + l2 + l1, {":3:", "time 456300.0 is not after previous 456300.1"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".nav";
    writeText(path, c.text);
    auto frags = c.fragments;
    frags.push_back(path);
    expectError([&] { readNav(path); }, frags);
  }
  expectError([&] { readNav(dir + "/missing.nav"); }, {dir + "/missing.nav", "cannot open"});
}

TEST(IoAtomic, FailedWriteKeepsPreviousFile) {
  const std::string dir = test::makeTempDir("io");
  const std::string path = dir + "/imu.txt";
  writeImu(path, randomImu(5, 100.0, false, 1));
  const auto size_before = std::filesystem::file_size(path);
  ImuSeries bad = randomImu(50, 100.0, false, 2);
  bad[40].t_s = bad[39].t_s - 1.0;
  EXPECT_THROW(writeImu(path, bad), std::invalid_argument);
  EXPECT_EQ(std::filesystem::file_size(path), size_before);
  EXPECT_EQ(readImu(path).size(), 5u);
}

}  // namespace
}  // namespace graftnav
