// The EKF, the smoother and `graftnav navigate` on the bundled simulated sample case
// (data/sample_tactical, simulator output read through core's readers).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "graftnav/io/case_config.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/filters/rts_smoother.h"
#include "test_support.h"

namespace graftnav {
namespace {

struct SampleCase {
  EstimationProblem problem;
  NavSeries truth;
};

SampleCase loadSample(bool tested) {
  const CasePaths paths(test::sourceDir() + "/data/sample_tactical");
  const CaseConfig cfg = loadCaseConfig(paths.caseYaml());
  SampleCase sc;
  ImuReadOptions ro;
  ro.nominal_rate_hz = tested ? cfg.testedImuRateHz() : cfg.imu_rate_hz;
  sc.problem.imu = readImu(tested ? paths.testedImu() : paths.refImu(), ro);
  sc.problem.gnss = readGnss(paths.gnssPos(), "");
  sc.truth = readNav(paths.truthNav());
  sc.problem.imu_profile = tested ? *cfg.tested_imu : *cfg.reference_imu;
  sc.problem.lever_arm_b_m = cfg.lever_arm_m.value_or(Eigen::Vector3d::Zero());
  sc.problem.initial =
      *interpolateNav(sc.truth, sc.problem.imu.front().t_s - sc.problem.imu.front().dt_s, 1e-3);
  return sc;
}

TEST(SampleCase, TacticalEkfConsistentAndRtsBeatsItInOutages) {
  SampleCase sc = loadSample(true);
  OutageScheduleConfig oc;
  oc.start_s = 60.0;
  oc.period_s = 300.0;  // three 60 s outages in the 14.5-min sample: most epochs have GNSS
  sc.problem.outages =
      buildOutageWindows(oc, sc.problem.imu.front().t_s, sc.problem.imu.back().t_s);
  ASSERT_GE(sc.problem.outages.size(), 2u);
  NavSolution fwd;
  const NavSolution rts = runRts(sc.problem, EkfOptions{}, &fwd);
  const Evaluation ef = evaluateSolution(fwd, sc.truth, sc.problem.outages);
  const Evaluation er = evaluateSolution(rts, sc.truth, sc.problem.outages);
  // With GNSS: centimetres (RTK-like 2 cm noise); in 60 s tactical outages: decimetres to metres.
  EXPECT_LT(ef.overall_rms.horizontal_m, 1.0);
  EXPECT_GT(ef.outage_rms.horizontal_m, 0.05);
  EXPECT_LT(er.outage_rms.horizontal_m, 0.5 * ef.outage_rms.horizontal_m);
  // Consistency, loosely (the simulated IMU has terms the 21 states do not model, and the
  // samples are correlated): NEES within a factor 2 of 9.
  EXPECT_GT(ef.nees_mean, 4.5);
  EXPECT_LT(ef.nees_mean, 18.0);
  EXPECT_GT(er.nees_mean, 4.5);
  EXPECT_LT(er.nees_mean, 18.0);
}

TEST(SampleCase, NavigateWritesTheErrorsJsonContract) {
  const std::string out = test::makeTempDir("navigate");
  const std::string cmd = test::graftnavBinary() + " navigate " + test::sourceDir() +
                          "/data/sample_tactical --out " + out +
                          " --imu tested --estimator rts --outage-length 30 --outage-period 90"
                          " --outage-start 60 --no-plots > " +
                          out + "/log.txt 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream f(out + "/errors.json");
  ASSERT_TRUE(f.good());
  const nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j["estimator"], "rts");
  EXPECT_TRUE(j["imu"].is_string());
  EXPECT_EQ(j["outages"]["length_s"], 30.0);
  EXPECT_GE(j["outages"]["count"].get<int>(), 3);
  for (const char* k :
       {"horizontal_rms_m", "vertical_rms_m", "roll_rms_deg", "pitch_rms_deg", "heading_rms_deg"}) {
    EXPECT_TRUE(j["overall"][k].is_number()) << k;
  }
  for (const char* s : {"outage", "outage_max"}) {
    for (const char* k : {"horizontal_m", "vertical_m", "roll_deg", "pitch_deg", "heading_deg"}) {
      EXPECT_TRUE(j[s][k].is_number()) << s << "." << k;
    }
  }
  EXPECT_TRUE(j["nees"].is_number());
  EXPECT_EQ(j.size(), 7u);  // exactly the contract's keys
  EXPECT_GE(j["outage_max"]["horizontal_m"].get<double>(),
            j["outage"]["horizontal_m"].get<double>());
  // solution.nav readable, one line per IMU epoch.
  EXPECT_GT(readNav(out + "/solution.nav").size(), 1000u);
  std::ifstream csv(out + "/outage_drift.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("max_horizontal_m"), std::string::npos);
}

TEST(SampleCase, NavigateFailsClearlyOnABadCaseDir) {
  const std::string out = test::makeTempDir("navigate_bad");
  const std::string cmd = test::graftnavBinary() + " navigate " + out + " --out " + out + "/o > " +
                          out + "/log.txt 2>&1";
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::ifstream f(out + "/log.txt");
  const std::string log((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(log.find("no case.yaml"), std::string::npos) << log;
}

}  // namespace
}  // namespace graftnav
