// `graftnav real`'s runs on a case made from the bundled sample, with toy estimators: streamed
// (nothing held: the IMU, the GNSS and the reference read as the estimator writes) and in memory,
// the same numbers and the same files, with the whole truth, a truth that ends before the
// solution, and one with a gap across an outage.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <utility>

#include "graftnav/navigate/real_run.h"
#include "graftnav/navigate/real_setup.h"
#include "test_support.h"
#include "toy_estimators.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

std::string fileText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The sample with its truth.nav's lines kept where keep(time) holds; a run config with 30-s
// outages every 120 s from 100 s, with or without a gnss: section (GNSS held or read as a file).
std::string makeCase(const std::string& dir, bool (*keep)(double t_s), bool gnss_section,
                     const std::string& run_config_extra = "") {
  const fs::path src = fs::path(test::sourceDir()) / "data/sample_tactical";
  fs::create_directories(fs::path(dir) / "field");
  fs::copy_file(src / "case.yaml", fs::path(dir) / "case.yaml");
  for (const char* f : {"tested_imu.txt", "gnss.pos"})
    fs::copy_file(src / "field" / f, fs::path(dir) / "field" / f);
  std::ifstream truth(src / "field/truth.nav");
  std::ofstream cut(fs::path(dir) / "field/truth.nav");
  std::string line;
  while (std::getline(truth, line)) {
    std::istringstream fields(line);
    int week = 0;
    double t_s = 0.0;
    fields >> week >> t_s;
    if (keep(t_s - 456340.0)) cut << line << "\n";
  }
  std::ofstream(fs::path(dir) / "run.yaml")
      << "outages: {length_s: 30, period_s: 120, start_s: 100}\n"
      << (gnss_section ? "gnss: {min_spacing_s: 0.05}\n" : "") << run_config_extra;
  return dir;
}

// real on the tested IMU of a case made by makeCase, with its run config.
RealRequest requestFor(const std::string& case_dir, std::vector<std::string> estimators) {
  RealRequest q;
  q.case_dir = case_dir;
  q.run_config = case_dir + "/run.yaml";
  q.imu = "tested";
  q.estimators = std::move(estimators);
  return q;
}

struct RealOutcome {
  RealInputs in;
  std::vector<EstimatorRun> rows;
};

RealOutcome runReal(const std::string& case_dir, const std::string& out, bool streamed) {
  const RealRequest q = requestFor(case_dir, {"hold"});
  const EstimatorRegistry registry = test::toyRegistry(streamed);
  RealOutcome o;
  o.in = loadRealInputs(q, registry, RunMessages{});
  std::vector<std::string> failed;
  o.rows = runRealEstimators(o.in, q.estimators, registry, out, RunMessages{}, &failed);
  EXPECT_TRUE(failed.empty());
  return o;
}

// Streamed and in memory on one case: the same numbers, the same files.
void expectSameRuns(const std::string& case_dir, bool reference_evaluated) {
  const RealOutcome s = runReal(case_dir, case_dir + "/streamed", true);
  const RealOutcome m = runReal(case_dir, case_dir + "/memory", false);
  EXPECT_TRUE(s.in.stream);
  EXPECT_TRUE(s.in.pr.imu.empty() && s.in.c.reference.empty());
  // The GNSS read as the estimator runs, unless selected (gnss:) or read by the alignment.
  if (!s.in.rc.gnss.given && s.in.rc.alignment.mode != AlignmentMode::kMotion) {
    EXPECT_TRUE(s.in.c.gnss.empty() && s.in.pr.gnss.empty());
    EXPECT_TRUE(s.in.pr.gnss_stream);
  }
  EXPECT_FALSE(m.in.stream);
  EXPECT_EQ(s.in.checkpoints_in_outages, m.in.checkpoints_in_outages);
  EXPECT_EQ(s.in.checkpoint_epochs, m.in.checkpoint_epochs);
  ASSERT_EQ(s.rows.size(), 1u);
  ASSERT_EQ(m.rows.size(), 1u);
  const EstimatorRun &a = s.rows[0], &b = m.rows[0];
  EXPECT_EQ(a.sol.gnss_used, b.sol.gnss_used);
  EXPECT_EQ(a.cp.n, b.cp.n);
  EXPECT_GT(a.cp.n, 100);  // 7 outages of 30 s, 1 Hz fixes
  EXPECT_EQ(a.cp.rms_h_m, b.cp.rms_h_m);
  EXPECT_EQ(a.cp.rms_of_max_h_m, b.cp.rms_of_max_h_m);
  EXPECT_EQ(a.cp.rms_v_m, b.cp.rms_v_m);
  ASSERT_EQ(a.ref.has_value(), b.ref.has_value());
  EXPECT_EQ(a.ref.has_value(), reference_evaluated);
  if (a.ref) {
    EXPECT_EQ(a.ref->outage_rms.horizontal_m, b.ref->outage_rms.horizontal_m);
    EXPECT_EQ(a.ref->outage_max_rms.horizontal_m, b.ref->outage_max_rms.horizontal_m);
    EXPECT_EQ(a.ref->overall_rms.heading_rad, b.ref->overall_rms.heading_rad);
    EXPECT_EQ(a.ref->outages.size(), b.ref->outages.size());
    EXPECT_GT(a.ref->outage_rms.horizontal_m, 0.1);
  }
  for (const char* f : {"solution.nav", "checkpoints.csv"}) {
    const std::string text = fileText(fs::path(case_dir) / "streamed/hold" / f);
    EXPECT_FALSE(text.empty()) << f;
    EXPECT_EQ(text, fileText(fs::path(case_dir) / "memory/hold" / f)) << f;
  }
}

TEST(RealRun, StreamedRunsGiveTheInMemoryNumbersAndFiles) {
  const std::string dir = test::makeTempDir("real_run_whole");
  expectSameRuns(makeCase(
                     dir + "/streamed_gnss", [](double) { return true; }, false),
                 true);
  expectSameRuns(makeCase(
                     dir + "/held_gnss", [](double) { return true; }, true),
                 true);
}

TEST(RealRun, AReferenceEndingEarlyOrWithAGapBehavesAsInMemory) {
  const std::string dir = test::makeTempDir("real_run_cut");
  // Ends at 600 s of 870 (the last outages have no reference epoch), and a gap from 330 to
  // 450 s across the outage at 340-370 s.
  expectSameRuns(makeCase(
                     dir + "/early", [](double t) { return t < 600.0; }, false),
                 true);
  expectSameRuns(makeCase(
                     dir + "/gap", [](double t) { return t < 330.0 || t > 450.0; }, false),
                 true);
}

TEST(RealRun, AStaticAlignmentStreamsFromItsWindowAndSkipsTheSamplesBefore) {
  // The sample stands still for its first 60 s: levelled over 20 s, the runs start at t0 + 20 s,
  // the streamed ones skipping the earlier samples as they read the file.
  const std::string dir = test::makeTempDir("real_run_static");
  const std::string c = makeCase(
      dir + "/static", [](double) { return true; }, false,
      "ekf: {alignment: static, static_alignment_s: 20}\n");
  expectSameRuns(c, true);
  const RealRequest q = requestFor(c, {"hold"});
  const RealInputs in = loadRealInputs(q, test::toyRegistry(true), RunMessages{});
  EXPECT_TRUE(in.stream);
  EXPECT_NEAR(in.imu_start_s, 456360.0, 1e-5);
  EXPECT_NEAR(in.pr.initial.t_s, 456360.0, 1e-9);
}

TEST(RealRun, AnInMotionAlignmentStreamsWithTheGnssHeld) {
  // Above 8 m/s from 456372 s: the alignment's GNSS epoch lies beyond the first 30-s prefix of
  // the file, which is read again longer; the runs start at that epoch, the streamed ones
  // skipping the earlier samples as they read the file.
  const std::string dir = test::makeTempDir("real_run_motion");
  const std::string c = makeCase(
      dir + "/motion", [](double) { return true; }, false,
      "ekf: {alignment: motion, motion_min_speed_m_s: 8}\n");
  expectSameRuns(c, true);
  const RealRequest q = requestFor(c, {"hold"});
  const RealInputs in = loadRealInputs(q, test::toyRegistry(true), RunMessages{});
  EXPECT_TRUE(in.stream);
  EXPECT_TRUE(in.pr.imu.empty());
  EXPECT_FALSE(in.pr.gnss.empty());  // held: the alignment reads the fixes
  EXPECT_FALSE(in.pr.gnss_stream);
  EXPECT_GT(in.pr.initial.t_s, 456340.0 + 30.0);  // beyond the first prefix
  EXPECT_NEAR(in.imu_start_s, in.pr.initial.t_s - 1e-6, 1e-9);
}

// The lines of `from` whose time (field `field`) keep(time) holds, written to `to`.
void copyLines(const fs::path& from, const fs::path& to, int field,
               const std::function<bool(double)>& keep) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    double t_s = 0.0;
    for (int i = 0; i <= field; ++i) fields >> t_s;
    if (keep(t_s)) out << line << "\n";
  }
}

// The sample cut by hand to [t0_s, t1_s]: the IMU from the sample that ends at t0_s (the next
// one's interval then starts there; the runs start at the initial state there and skip it), the
// GNSS and the truth inside; the outages of `run_yaml` start from the file's first interval, 50 Hz
// earlier.
std::string makeCutCase(const std::string& dir, double t0_s, double t1_s,
                        const std::string& run_yaml) {
  const fs::path src = fs::path(test::sourceDir()) / "data/sample_tactical";
  const fs::path d(dir);
  fs::create_directories(d / "field");
  fs::copy_file(src / "case.yaml", d / "case.yaml");
  const auto inside = [=](double t) { return t >= t0_s && t <= t1_s; };
  copyLines(src / "field/tested_imu.txt", d / "field/tested_imu.txt", 0,
            [=](double t) { return t >= t0_s - 1e-6 && t <= t1_s; });
  copyLines(src / "field/gnss.pos", d / "field/gnss.pos", 0, inside);
  copyLines(src / "field/truth.nav", d / "field/truth.nav", 1, inside);
  std::ofstream(d / "run.yaml") << run_yaml;
  return dir;
}

// real with a time range (the run config's) gives, estimator by estimator, the solution and the
// check point errors of its run on the case cut to the range by hand, streamed and in memory,
// with the GNSS read as a file and held (gnss:).
TEST(RealRun, ARangeGivesTheRunOnTheCaseCutToItByHand) {
  const std::string dir = test::makeTempDir("real_run_range");
  for (const bool gnss_section : {false, true}) {
    const std::string gnss = gnss_section ? "gnss: {min_spacing_s: 0.05}\n" : "";
    const std::string whole = makeCase(
        dir + "/whole" + gnss.substr(0, 4), [](double) { return true; }, gnss_section,
        "time_range: {start_s: 456500, end_s: 456900}\n");
    const std::string cut =
        makeCutCase(dir + "/cut" + gnss.substr(0, 4), 456500.0, 456900.0,
                    "outages: {length_s: 30, period_s: 120, start_s: 100.02}\n" + gnss);
    for (const bool streamed : {true, false}) {
      const std::string tag = (streamed ? "/streamed" : "/memory") + std::string("/");
      const RealOutcome a = runReal(whole, whole + tag, streamed);
      const RealOutcome b = runReal(cut, cut + tag, streamed);
      EXPECT_EQ(a.in.stream, streamed);
      EXPECT_EQ(a.in.time_range.startS(), 456500.0);
      EXPECT_NEAR(a.in.pr.initial.t_s, 456500.0, 1e-9);
      EXPECT_EQ(a.in.checkpoints_in_outages, b.in.checkpoints_in_outages);
      EXPECT_EQ(a.in.checkpoint_epochs, b.in.checkpoint_epochs);
      EXPECT_EQ(a.in.checkpoint_epochs, 401);  // 1 Hz fixes over 400 s
      ASSERT_EQ(a.rows.size(), 1u);
      ASSERT_EQ(b.rows.size(), 1u);
      const EstimatorRun &x = a.rows[0], &y = b.rows[0];
      EXPECT_EQ(x.sol.gnss_used, y.sol.gnss_used);
      EXPECT_EQ(x.cp.n, y.cp.n);
      EXPECT_GT(x.cp.n, 80);  // 3 outages of 30 s
      EXPECT_EQ(x.cp.rms_h_m, y.cp.rms_h_m);
      EXPECT_EQ(x.cp.rms_of_max_h_m, y.cp.rms_of_max_h_m);
      EXPECT_EQ(x.cp.rms_v_m, y.cp.rms_v_m);
      ASSERT_TRUE(x.ref && y.ref);
      EXPECT_EQ(x.ref->outage_rms.horizontal_m, y.ref->outage_rms.horizontal_m);
      EXPECT_EQ(x.ref->outage_max_rms.horizontal_m, y.ref->outage_max_rms.horizontal_m);
      for (const char* f : {"hold/solution.nav", "hold/checkpoints.csv"}) {
        const std::string text = fileText(whole + tag + f);
        EXPECT_FALSE(text.empty()) << f;
        EXPECT_EQ(text, fileText(cut + tag + f)) << f << tag << gnss;
      }
    }
  }
}

TEST(RealRun, AFailedEstimatorLeavesNoFolderAndTheOthersRun) {
  const std::string dir = test::makeTempDir("real_run_failed");
  const std::string c = makeCase(
      dir + "/case", [](double) { return true; }, false);
  const RealRequest q = requestFor(c, {"nope", "hold"});
  const EstimatorRegistry registry = test::toyRegistry(true);
  const RealInputs in = loadRealInputs(q, registry, RunMessages{});
  EXPECT_FALSE(in.stream);  // an unknown name has no streamed form: its failure is listed
  std::vector<std::string> failed;
  const auto rows = runRealEstimators(in, q.estimators, registry, dir + "/out", {}, &failed);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].rfind("nope: ", 0), 0u);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_FALSE(fs::exists(dir + "/out/nope"));
  EXPECT_TRUE(fs::exists(dir + "/out/hold/solution.nav"));
}

TEST(RealRun, ANonFiniteStateFailsTheRunAsInMemory) {
  const std::string dir = test::makeTempDir("real_run_nan");
  const std::string c = makeCase(
      dir + "/case", [](double) { return true; }, false);
  const RealRequest q = requestFor(c, {"broken", "hold"});
  std::vector<std::string> failed[2];
  for (int streamed : {0, 1}) {
    EstimatorRegistry registry = test::toyRegistry(streamed);
    registry.add(test::toyEntry("broken", std::nan(""), 0.5, streamed));
    const RealInputs in = loadRealInputs(q, registry, RunMessages{});
    EXPECT_EQ(in.stream, streamed == 1);
    const std::string out = dir + "/out" + std::to_string(streamed);
    EXPECT_EQ(runRealEstimators(in, q.estimators, registry, out, {}, &failed[streamed]).size(), 1u);
    EXPECT_FALSE(fs::exists(out + "/broken")) << streamed;
  }
  ASSERT_EQ(failed[1].size(), 1u);
  EXPECT_EQ(failed[1], failed[0]);
  EXPECT_EQ(failed[1][0].rfind("broken: non-finite state at t=", 0), 0u) << failed[1][0];
}

}  // namespace
}  // namespace graftnav
