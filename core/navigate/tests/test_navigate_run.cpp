// The navigate pipeline on the bundled sample with a toy estimator: a streamed run and an
// in-memory run write the same files byte for byte, the setup holds no series when it streams,
// and its checks stop a run before any file is written.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "graftnav/navigate/navigate_run.h"
#include "graftnav/navigate/navigate_setup.h"
#include "test_support.h"
#include "toy_estimators.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;
using test::toyRegistry;
using ::testing::HasSubstr;

NavigateRequest sampleRequest(const std::string& out) {
  NavigateRequest q;
  q.case_dir = test::sourceDir() + "/data/sample_tactical";
  q.out_dir = out;
  q.imu = "tested";
  q.estimator = "hold";
  q.outage.length_s = 30.0;
  q.outage.period_s = 120.0;
  q.outage.start_s = 100.0;
  return q;
}

std::string fileText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

NavigateOutcome runInto(const NavigateRequest& q, const EstimatorRegistry& r,
                        NavigateSetup* setup = nullptr) {
  fs::create_directories(q.out_dir);
  const NavigateSetup s = prepareNavigate(q, r, RunMessages{});
  if (setup) *setup = s;
  return runNavigate(s, q.out_dir, r, RunMessages{});
}

TEST(NavigateRun, StreamedAndInMemoryRunsWriteTheSameFiles) {
  const std::string dir = test::makeTempDir("navigate_run");
  const NavigateRequest streamed_q = sampleRequest(dir + "/streamed");
  const NavigateRequest memory_q = sampleRequest(dir + "/memory");
  NavigateSetup streamed_setup, memory_setup;
  const NavigateOutcome streamed = runInto(streamed_q, toyRegistry(true), &streamed_setup);
  const NavigateOutcome memory = runInto(memory_q, toyRegistry(false), &memory_setup);

  EXPECT_TRUE(streamed_setup.stream);
  EXPECT_TRUE(streamed_setup.stream_gnss);
  EXPECT_TRUE(streamed_setup.pr.imu.empty());  // nothing held: the run reads the file
  EXPECT_TRUE(streamed_setup.c.reference.empty());
  EXPECT_FALSE(memory_setup.stream);
  EXPECT_FALSE(memory_setup.pr.imu.empty());
  EXPECT_TRUE(streamed.solution.states.empty());
  EXPECT_EQ(memory.solution.states.size(), memory.files.epochs);
  EXPECT_EQ(streamed.files.epochs, memory.files.epochs);
  EXPECT_EQ(streamed.files.epochs, 43500u);
  ASSERT_TRUE(streamed.evaluation && memory.evaluation);
  EXPECT_EQ(streamed.evaluation->outages.size(), 7u);  // 100 s, 220 s, ... 820 s of 870 s
  EXPECT_GT(streamed.evaluation->outage_rms.horizontal_m, 0.1);
  for (const char* f : {"solution.nav", "imu_errors.txt", "state_std.txt", "errors.json",
                        "errors.csv", "outage_drift.csv"}) {
    const std::string a = fileText(fs::path(streamed_q.out_dir) / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, fileText(fs::path(memory_q.out_dir) / f)) << f;
  }
  EXPECT_THAT(fileText(fs::path(streamed_q.out_dir) / "run_info.json"), HasSubstr("reference: "));
}

TEST(NavigateRun, ARunWithoutGnssStopsBeforeItsFilesAreCommitted) {
  const std::string dir = test::makeTempDir("navigate_run_nognss");
  for (bool streamed : {true, false}) {
    const NavigateRequest q = sampleRequest(dir + (streamed ? "/s" : "/m"));
    EXPECT_THROW(runInto(q, toyRegistry(streamed, 0)), std::runtime_error);
    EXPECT_FALSE(fs::exists(fs::path(q.out_dir) / "solution.nav")) << streamed;
  }
}

TEST(NavigateRun, AnEstimatorWithoutGnssNeedsNoOutagesNorProfile) {
  const std::string dir = test::makeTempDir("navigate_run_coast");
  NavigateRequest q = sampleRequest(dir);
  q.estimator = "coast";
  NavigateSetup s;
  const NavigateOutcome o = runInto(q, toyRegistry(false), &s);
  EXPECT_FALSE(s.uses_gnss);
  EXPECT_TRUE(s.pr.outages.empty());  // the outage overrides apply to GNSS only
  EXPECT_TRUE(s.c.gnss.empty());
  EXPECT_EQ(o.files.epochs, 43500u);
}

TEST(NavigateRun, SetupChecksStopTheRun) {
  const std::string dir = test::makeTempDir("navigate_run_checks");
  NavigateRequest q = sampleRequest(dir);
  q.estimator = "nope";
  EXPECT_THROW(prepareNavigate(q, toyRegistry(true), RunMessages{}), std::runtime_error);
  q = sampleRequest(dir);
  q.outage.start_s = 1e6;  // after the end of the data
  EXPECT_THROW(prepareNavigate(q, toyRegistry(true), RunMessages{}), std::runtime_error);
  q = sampleRequest(dir);
  q.run_config = dir + "/missing.yaml";
  EXPECT_THROW(prepareNavigate(q, toyRegistry(true), RunMessages{}), std::exception);
}

TEST(NavigateRun, WarningsReachTheMessages) {
  const std::string dir = test::makeTempDir("navigate_run_warnings");
  NavigateRequest q = sampleRequest(dir);
  q.run_config = dir + "/run.yaml";
  std::ofstream(q.run_config) << "ekf:\n  no_such_key: 1\n";
  std::vector<std::string> warnings;
  RunMessages m;
  m.on_warning = [&](const std::string& w) { warnings.push_back(w); };
  prepareNavigate(q, toyRegistry(true), m);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings.front(), HasSubstr("no_such_key"));
}

}  // namespace
}  // namespace graftnav
