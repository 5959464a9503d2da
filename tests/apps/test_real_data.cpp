// Real recordings (../shared/data/real, read in place: the sources carry no licence file, so no
// slice is copied into the repository). Every test is skipped with a message when the data are absent.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "graftnav/io/gnss_io.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/io/nav_io.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

std::string realCase(const std::string& name) { return test::sharedDir() + "/data/real/" + name; }

#define SKIP_WITHOUT(dir) GRAFTNAV_REQUIRE_SHARED_PATH(dir)

GnssSeries readYandldGnss(std::vector<ReadReport>* reports) {
  const std::string d = realCase("yandld_20220405_rtk") + "/field/";
  return readGnss(d + "gnss.pos", d + "gnss_fixtype.txt", GnssReadPolicy::real(), reports);
}

TEST(RealData, YandldGnssSelectionCountsEveryEpochAndReadersAreNotSilent) {
  SKIP_WITHOUT(realCase("yandld_20220405_rtk"));
  std::vector<ReadReport> reports;
  const GnssSeries g = readYandldGnss(&reports);
  ASSERT_EQ(g.size(), 7267u);  // README: all 7267 epochs kept
  // Epochs off whole seconds (10 Hz) are reported by the real policy, with a count.
  bool reported = false;
  for (const auto& r : reports) reported = reported || !r.summary().empty();
  EXPECT_TRUE(reported);
  GnssSelectionOptions o;
  o.accepted_fix_types = {4, 5};
  const GnssSelection s = selectGnss(g, o);
  EXPECT_EQ(s.counts.input_by_fix_type.at(1), 6622);  // CONVERSION_LOG fix type counts
  EXPECT_EQ(s.counts.used_by_fix_type.at(4), 463);
  EXPECT_EQ(s.counts.used_by_fix_type.at(5), 182);
  EXPECT_EQ(s.counts.rejected_fix_type, 6622);
  EXPECT_EQ(s.counts.used + s.counts.rejected(), s.counts.input);
}

TEST(RealData, YandldRtkLatencyAgainstTheReferenceSlice) {
  SKIP_WITHOUT(realCase("yandld_20220405_rtk"));
  const GnssSeries g = readYandldGnss(nullptr);
  const NavSeries ref_all =
      readNav(realCase("yandld_20220405_rtk") + "/field/reference.nav", NavReadPolicy::real());
  // A 250-s slice (t0+250..t0+500 s) of the drive.
  const double t0 = ref_all.front().t_s;
  NavSeries ref;
  for (const auto& s : ref_all)
    if (s.t_s >= t0 + 250.0 && s.t_s <= t0 + 500.0) ref.push_back(s);
  const GnssSeries rtk = gnssOfFixTypes(g, {4}, GnssSelectionOptions{});
  const GnssSeries spp = gnssOfFixTypes(g, {1}, GnssSelectionOptions{});
  LatencyScanOptions lo;
  lo.outlier_m = 3.0;
  const LatencyEstimate e4 = estimateGnssLatency(ref, rtk, Eigen::Vector3d::Zero(), lo);
  lo.outlier_m = 10.0;
  const LatencyEstimate e1 = estimateGnssLatency(ref, spp, Eigen::Vector3d::Zero(), lo);
  // README/CONVERSION_LOG: RTK-fixed epochs are stamped later than the place was passed
  // (median 0.4 s, p5..p95 -0.1..2.1 s); single-point ones earlier (0..0.3 s, median 0.26 s).
  EXPECT_GT(e4.grid_s, 0.2);
  EXPECT_LT(e4.grid_s, 1.2);
  EXPECT_LT(e1.grid_s, 0.0);
  EXPECT_GT(e1.grid_s, -0.8);
  EXPECT_LT(e4.grid_rms_h_m, 0.5 * e4.rms_h_at_zero_m);  // the shift explains most of the residual
  EXPECT_GE(e4.fixes_used, 15) << "tau4 " << e4.grid_s << " tau1 " << e1.grid_s;
  std::printf("slice: RTK-fixed tau %.3f s (%d fixes), single-point tau %.3f s (%d fixes)\n",
              e4.grid_s, e4.fixes_used, e1.grid_s, e1.fixes_used);
}

TEST(RealData, WidCarGraftedDotFromItsOwnStandstill) {
  const std::string dir = realCase("wid_car_trial07");
  SKIP_WITHOUT(dir);
  const std::string src = test::sourceDir();
  const std::string out = test::makeTempDir("real_sg");
  const std::string log = out + "/log.txt";
  const std::string cmd =
      test::graftnavBinary() + " real-sg '" + dir + "' --out '" + out +
      "' --estimator ekf --run-config '" + src + "/configs/real/wid_car.yaml' --ref-profile '" +
      src + "/configs/real/wid_mrup.yaml' --tested-profile '" + src +
      "/configs/real/wid_dot.yaml' --static-gyro-threshold 0.02 --static-accel-threshold 0.65 > '" +
      log + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream f(out + "/standstills.md");
  ASSERT_TRUE(f.good());
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string md = ss.str();
  // The DOT's standstill gyro bias (README: about [-0.82, -1.00, -0.26] deg/s FRD).
  std::smatch m;
  ASSERT_TRUE(std::regex_search(md, m, std::regex(R"(gyro \[(\S+) (\S+) (\S+)\] deg/s)"))) << md;
  EXPECT_NEAR(std::stod(m[1]), -0.82, 0.05);
  EXPECT_NEAR(std::stod(m[2]), -1.00, 0.05);
  EXPECT_NEAR(std::stod(m[3]), -0.26, 0.05);
  // K realizations like `evaluate` (the same default K and the same keys): SG#1 only, since a
  // standstill gives no dynamic model.
  std::ifstream jf(out + "/evaluation.json");
  const auto j = nlohmann::json::parse(jf);
  EXPECT_EQ(j["realizations"], 20);
  EXPECT_FALSE(j["predictive"].contains("SG2"));
  for (const std::string s :
       {"horizontal_m", "vertical_m", "roll_deg", "pitch_deg", "heading_deg"}) {
    const auto& p = j["predictive"]["SG1"][s];
    EXPECT_LE(p["p05"].get<double>(), p["p95"].get<double>()) << s;
    const double real = j["err"]["REAL"][s];
    const std::string v = j["verdict"]["SG1"][s];
    EXPECT_EQ(v, real < p["p05"].get<double>()   ? "pessimistic"
                 : real > p["p95"].get<double>() ? "optimistic"
                                                 : "consistent")
        << s;
    EXPECT_GE(j["real_percentile"]["SG1"][s].get<double>(), 0.0);
    EXPECT_LE(j["diff_interval"]["SG1"][s][0].get<double>(),
              j["diff_interval"]["SG1"][s][1].get<double>());
  }
  std::ifstream tf(out + "/tables.md");
  std::stringstream ts;
  ts << tf.rdbuf();
  EXPECT_NE(ts.str().find("REAL in SG#1"), std::string::npos);
  // The log states the reader results and the GNSS selection counts (never silent).
  std::ifstream lf(log);
  std::stringstream ls;
  ls << lf.rdbuf();
  EXPECT_NE(ls.str().find("GNSS selection: 751 epochs"), std::string::npos);
  EXPECT_NE(ls.str().find("reader"), std::string::npos);
}

// `real` on the car trial with all four estimators: its 5 Hz RTK stream (stamps jittered by
// 10-20 ms, gaps up to 0.6 s) once made the factor graphs fail with a one-sample preintegration.
// Pinned: every estimator runs, and its check point error stays where it is (ekf 3.3 m, rts 0.28 m,
// fgo 0.27 m, fgo-window 4.1 m RMS horizontal over the 300 withheld fixes of the three 20-s
// outages).
TEST(RealData, WidCarRealRunsEveryEstimator) {
  const std::string dir = realCase("wid_car_trial07");
  SKIP_WITHOUT(dir);
  const std::string src = test::sourceDir();
  const std::string out = test::makeTempDir("real_wid_all");
  const std::string cmd = test::graftnavBinary() + " real '" + dir + "' --out '" + out +
                          "/o' --run-config '" + src + "/configs/real/wid_car.yaml' --profile '" +
                          src + "/configs/real/wid_mrup.yaml' --estimator ekf,rts,fgo,fgo-window" +
                          " --no-plots > '" + out + "/log.txt' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream jf(out + "/o/summary.json");
  const auto j = nlohmann::json::parse(jf);
  EXPECT_TRUE(j["failed"].empty()) << j["failed"].dump();
  const std::map<std::string, double> max_rms_h_m = {
      {"ekf", 5.0}, {"rts", 0.5}, {"fgo", 0.5}, {"fgo-window", 6.0}};
  std::set<std::string> seen;
  for (const auto& e : j["estimators"]) {
    const std::string name = e["estimator"];
    seen.insert(name);
    EXPECT_EQ(e["checkpoints"]["n"].get<int>(), 300) << name;
    EXPECT_LT(e["checkpoints"]["rms_h_m"].get<double>(), max_rms_h_m.at(name)) << name;
    EXPECT_GT(e["gnss"]["used"].get<int>(), 300) << name;
  }
  EXPECT_EQ(seen.size(), 4u);
}

// What further two-IMU recordings do to the mismatch finder, made from wid_car_trial07: the DOT's
// tags 1.7 s late (loggers started apart) and 2.5 s of DOT packets lost; and a slice that never
// stands still. The first must give tau = 1.7 s plus the recording's own -25 ms and list the gap;
// the second must run with the reference alone as the simulation.
TEST(RealData, WidCarDiagnoseSurvivesLoggerOffsetLostPacketsAndNoStandstill) {
  const std::string dir = realCase("wid_car_trial07");
  SKIP_WITHOUT(dir);
  const std::string out = test::makeTempDir("real_diag");
  auto makeCase = [&](const std::string& name, double shift_s, long drop_a, long drop_b,
                      double t_min, double t_max) {
    const std::string c = out + "/" + name;
    fs::create_directories(c + "/field");
    fs::copy_file(dir + "/case.yaml", c + "/case.yaml");
    fs::copy_file(dir + "/field/gnss.pos", c + "/field/gnss.pos");
    for (const std::string f : {"ref_imu", "tested_imu"}) {
      std::ifstream in(dir + "/field/" + f + ".txt");
      std::ofstream o(c + "/field/" + f + ".txt");
      std::string line;
      long k = 0;
      while (std::getline(in, line)) {
        ++k;
        std::istringstream ls(line);
        double t = 0.0;
        ls >> t;
        if (t <= t_min || t >= t_max) continue;
        if (f == "tested_imu") {
          if (k >= drop_a && k <= drop_b) continue;
          char buf[32];
          std::snprintf(buf, sizeof buf, "%.6f", t + shift_s);
          o << buf << line.substr(line.find_first_of(" \t")) << "\n";
        } else {
          o << line << "\n";
        }
      }
    }
    return c;
  };
  auto diagnoseJson = [&](const std::string& c) {
    const std::string o = c + "_out";
    const std::string cmd = test::graftnavBinary() + " diagnose '" + c + "' --out '" + o +
                            "' --no-plots > '" + o + ".log' 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream f(o + "/diagnosis.json");
    return nlohmann::json::parse(f);
  };
  auto effect = [](const nlohmann::json& js, const std::string& name) {
    for (const auto& e : js["effects"])
      if (e["name"] == name) return e;
    return nlohmann::json();
  };
  const nlohmann::json js = diagnoseJson(makeCase("offset_gap", 1.7, 6000, 6300, 0.0, 1e9));
  const nlohmann::json to = effect(js, "time_offset");
  ASSERT_FALSE(to.is_null()) << js.dump(1);
  EXPECT_NEAR(to["parameters"]["tau_s"].get<double>(), 1.7 - 0.0254, 0.003);
  EXPECT_EQ(js["masked_spans"].size(), 1u) << "the lost packets are listed";

  const nlohmann::json js2 = diagnoseJson(makeCase("moving", 0.0, 0, -1, 100035.0, 100072.0));
  EXPECT_NE(js2["notes"].dump().find("no static span in the tested record"), std::string::npos)
      << js2.dump(1);
  EXPECT_FALSE(effect(js2, "time_offset").is_null()) << js2.dump(1);
}

// A diagnose option out of range is refused naming the file, the option and its value.
TEST(RealData, DiagnoseConfigOutOfRangeNamesFileKeyAndValue) {
  const std::string dir = realCase("wid_car_trial07");
  SKIP_WITHOUT(dir);
  const std::string out = test::makeTempDir("diag_cfg");
  {
    std::ofstream c(out + "/bad.yaml");
    c << "realign_offset_s: -1\n";
  }
  const std::string log = out + "/log.txt";
  const std::string cmd = test::graftnavBinary() + " diagnose '" + dir + "' --out '" + out +
                          "/o' --no-plots --options '" + out + "/bad.yaml' > '" + log + "' 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::ifstream lf(log);
  std::stringstream ls;
  ls << lf.rdbuf();
  EXPECT_NE(ls.str().find(out + "/bad.yaml: DiagnoseOptions: realign_offset_s = -1"),
            std::string::npos)
      << ls.str();
}

TEST(RealData, RunConfigGnssSectionIsValidatedWithFileAndKey) {
  const std::string dir = realCase("wid_car_trial07");
  SKIP_WITHOUT(dir);
  const std::string out = test::makeTempDir("real_cfg");
  {
    std::ofstream c(out + "/bad.yaml");
    c << "outages: {length_s: 20, period_s: 35, start_s: 55}\ngnss:\n  max_horizontal_std_m: 0\n";
  }
  const std::string log = out + "/log.txt";
  const std::string cmd = test::graftnavBinary() + " real '" + dir + "' --out '" + out +
                          "/o' --imu ref --profile '" + test::sourceDir() +
                          "/configs/real/wid_mrup.yaml' --estimator ekf --run-config '" + out +
                          "/bad.yaml' > '" + log + "' 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::ifstream lf(log);
  std::stringstream ls;
  ls << lf.rdbuf();
  EXPECT_NE(ls.str().find("bad.yaml: section gnss"), std::string::npos) << ls.str();
  EXPECT_NE(ls.str().find("max_horizontal_std_m"), std::string::npos) << ls.str();
}

}  // namespace
}  // namespace graftnav
