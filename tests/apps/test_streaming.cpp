// The streamed estimators (IMU read in blocks, solution written as it goes) against the in-memory
// ones on the bundled sample: solution.nav byte-identical, every other output number equal
// (ekf, rts, fgo-window, fgo), with the GNSS held or read from its file epoch by epoch; the
// command's evaluation against the streamed truth byte-identical to the in-memory one.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/evaluation_files.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/filters/rts_smoother.h"
#include "graftnav/graph/fgo_solver.h"
#include "graftnav/io/case_config.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/nav_interp.h"
#include "test_support.h"

namespace graftnav {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string sampleDir() { return test::sourceDir() + "/data/sample_mems"; }

// The problem `graftnav navigate data/sample_mems --imu tested --outage-length 60
// --outage-period 180` builds: initial state from truth.nav at the first IMU interval's start.
EstimationProblem sampleProblem() {
  const CasePaths paths(sampleDir());
  const CaseConfig cfg = loadCaseConfig(paths.caseYaml());
  EstimationProblem p;
  ImuReadOptions ro;
  ro.nominal_rate_hz = cfg.testedImuRateHz();
  p.imu = readImu(paths.testedImu(), ro);
  p.gnss = readGnssPos(paths.gnssPos());
  p.imu_profile = cfg.tested_imu.value();
  p.lever_arm_b_m = cfg.lever_arm_m.value();
  const NavSeries truth = readNav(paths.truthNav());
  const double t_first = p.imu.front().t_s - p.imu.front().dt_s;
  p.initial = interpolateNav(truth, std::max(t_first, truth.front().t_s), 1e-3).value();
  p.initial.gnss_week = cfg.gnss_week.value();
  OutageScheduleConfig oc;
  oc.length_s = 60.0;
  oc.period_s = 180.0;
  p.outages = buildOutageWindows(oc, t_first, p.imu.back().t_s);
  return p;
}

// The sample's GNSS file read epoch by epoch, as `navigate` streams it.
class GnssFileSource : public GnssSource {
 public:
  GnssFileSource() : reader_(CasePaths(sampleDir()).gnssPos(), "") {}
  bool next(GnssFix* fix) override { return reader_.next(fix); }

 private:
  GnssStreamReader reader_;
};

// The problem without the samples (the streamed run must not need them), its GNSS held or
// streamed from the file.
EstimationProblem streamedHeader(const EstimationProblem& problem, bool gnss_from_file) {
  EstimationProblem header = problem;
  header.imu.clear();
  if (gnss_from_file) {
    header.gnss.clear();
    header.gnss_stream = [] { return std::make_unique<GnssFileSource>(); };
  }
  return header;
}

// Writes solution.nav and keeps the epochs, as `navigate` does with a reference.
class TeeSink : public SolutionSink {
 public:
  TeeSink(const std::string& path, NavSolution* keep) : writer_(path), keep_(keep) {}
  void add(const NavState& s, const PvaSigma* sigma, const ImuErrorEstimate& e) override {
    writer_.add(s);
    keep_.add(s, sigma, e);
  }
  void commit() { writer_.commit(); }

 private:
  NavWriter writer_;
  NavSolutionSink keep_;
};

// Reads the sample's tested IMU in blocks of `block` samples (odd sizes put GNSS epochs and
// record boundaries at every position in a block).
ImuPassFn filePass(std::size_t block) {
  return [block](const ImuBlockFn& fn) {
    const CasePaths paths(sampleDir());
    ImuReadOptions ro;
    ro.nominal_rate_hz = loadCaseConfig(paths.caseYaml()).testedImuRateHz();
    ImuBlockReader reader(paths.testedImu(), ro, block);
    ImuSeries samples;
    while (reader.next(&samples)) fn(samples);
  };
}

void expectSameSolution(const NavSolution& memory, const NavSolution& streamed) {
  EXPECT_EQ(memory.gnss_used, streamed.gnss_used);
  EXPECT_EQ(memory.gnss_rejected, streamed.gnss_rejected);
  EXPECT_EQ(memory.gnss_withheld, streamed.gnss_withheld);
  EXPECT_EQ(memory.estimator, streamed.estimator);
  ASSERT_EQ(memory.states.size(), streamed.states.size());
  ASSERT_EQ(memory.sigma.size(), streamed.sigma.size());
  for (std::size_t k = 0; k < memory.states.size(); ++k) {
    ASSERT_EQ(memory.states[k].t_s, streamed.states[k].t_s) << k;
    ASSERT_EQ(memory.sigma[k], streamed.sigma[k]) << k;
    ASSERT_EQ(memory.gyro_bias_rad_s[k], streamed.gyro_bias_rad_s[k]) << k;
    ASSERT_EQ(memory.accel_scale[k], streamed.accel_scale[k]) << k;
  }
}

struct Case {
  const char* estimator;
  int decimation;
  std::size_t block;
  bool gnss_from_file;
};

class StreamedEstimator : public ::testing::TestWithParam<Case> {};

TEST_P(StreamedEstimator, SolutionFileByteIdenticalToInMemory) {
  const Case c = GetParam();
  const EstimationProblem problem = sampleProblem();
  EkfOptions o;
  o.output_decimation = c.decimation;
  const bool rts = std::string(c.estimator) == "rts";
  const NavSolution memory = rts ? runRts(problem, o) : runEkf(problem, o);
  ASSERT_GT(memory.states.size(), 1000u);
  const std::string dir = test::makeTempDir("streaming");
  writeNav(dir + "/memory.nav", memory.states);

  const EstimationProblem header = streamedHeader(problem, c.gnss_from_file);
  NavSolution streamed;
  TeeSink sink(dir + "/streamed.nav", &streamed);
  const NavSolution book = rts ? runRtsStreaming(header, o, filePass(c.block), sink)
                               : runEkfStreaming(header, o, filePass(c.block), sink);
  sink.commit();
  streamed.estimator = book.estimator;
  streamed.gnss_used = book.gnss_used;
  streamed.gnss_rejected = book.gnss_rejected;
  streamed.gnss_withheld = book.gnss_withheld;
  expectSameSolution(memory, streamed);
  const std::string a = slurp(dir + "/memory.nav"), b = slurp(dir + "/streamed.nav");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "solution.nav differs between the in-memory and the streamed "
                      << c.estimator;
}

INSTANTIATE_TEST_SUITE_P(EkfAndRts, StreamedEstimator,
                         ::testing::Values(Case{"ekf", 1, 4096, false}, Case{"ekf", 3, 37, true},
                                           Case{"ekf", 1, 4096, true}, Case{"rts", 1, 4096, false},
                                           Case{"rts", 3, 37, true}, Case{"rts", 1, 1, false}));

// The factor graphs with the samples read from the file in blocks (the window holding only its
// intervals' samples, the batch re-reading the file for re-preintegration and output) against
// the in-memory ones: every epoch equal to the last bit, solution.nav byte-identical. This holds
// because the graphs are deterministic: the window removes a marginalized node's factors in a
// fixed order (Ceres' own removal follows a hash set of addresses, which moved the results
// by ~1e-5 m with the heap layout).
struct GraphCase {
  bool window;
  bool fixed_lag;
  std::size_t block;
  bool gnss_from_file;
};

class StreamedFactorGraph : public ::testing::TestWithParam<GraphCase> {};

TEST_P(StreamedFactorGraph, SolutionFileByteIdenticalToInMemory) {
  const GraphCase c = GetParam();
  const EstimationProblem problem = sampleProblem();
  FgoOptions o;
  o.window_fixed_lag_output = c.fixed_lag;
  const NavSolution memory = c.window ? solveWindowFgo(problem, o) : solveBatchFgo(problem, o);
  ASSERT_GT(memory.states.size(), problem.imu.size() / 2);
  const std::string dir = test::makeTempDir("streaming_graph");
  writeNav(dir + "/memory.nav", memory.states);

  const EstimationProblem header = streamedHeader(problem, c.gnss_from_file);
  NavSolution streamed;
  TeeSink sink(dir + "/streamed.nav", &streamed);
  const FgoEpochFn out = [&](const NavState& s, const PvaSigma* sigma, const ImuErrorEstimate& e) {
    sink.add(s, sigma, e);
  };
  const NavSolution book = c.window ? solveWindowFgo(header, filePass(c.block), o, nullptr, out)
                                    : solveBatchFgo(header, filePass(c.block), o, nullptr, out);
  sink.commit();
  EXPECT_TRUE(book.states.empty());
  EXPECT_EQ(book.gnss_used, memory.gnss_used);
  EXPECT_EQ(book.gnss_rejected, memory.gnss_rejected);
  EXPECT_EQ(book.gnss_withheld, memory.gnss_withheld);
  ASSERT_EQ(streamed.states.size(), memory.states.size());
  EXPECT_EQ(streamed.sigma.size(), memory.sigma.size());
  for (std::size_t k = 0; k < memory.states.size(); ++k) {
    const NavState& a = memory.states[k];
    const NavState& b = streamed.states[k];
    ASSERT_EQ(a.t_s, b.t_s) << k;
    ASSERT_EQ(a.pos.lat_rad, b.pos.lat_rad) << k;
    ASSERT_EQ(a.pos.lon_rad, b.pos.lon_rad) << k;
    ASSERT_EQ(a.pos.h_m, b.pos.h_m) << k;
    ASSERT_EQ(a.v_n, b.v_n) << k;
    ASSERT_EQ(a.q_nb.coeffs(), b.q_nb.coeffs()) << k;
    ASSERT_EQ(memory.gyro_bias_rad_s[k], streamed.gyro_bias_rad_s[k]) << k;
    ASSERT_EQ(memory.accel_bias_m_s2[k], streamed.accel_bias_m_s2[k]) << k;
  }
  const std::string a = slurp(dir + "/memory.nav"), b = slurp(dir + "/streamed.nav");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "solution.nav differs between the in-memory and the streamed graph";
}

INSTANTIATE_TEST_SUITE_P(WindowAndBatch, StreamedFactorGraph,
                         ::testing::Values(GraphCase{true, false, 4096, false},
                                           GraphCase{true, false, 37, true},
                                           GraphCase{true, true, 37, true},
                                           GraphCase{false, false, 37, true}));

// The CLI streams ekf, rts and the factor graphs: its solution.nav equals the in-memory run's to
// the last digit.
NavSolution inMemorySolution(const std::string& estimator, const EstimationProblem& problem) {
  if (estimator == "rts") return runRts(problem, EkfOptions{});
  if (estimator == "fgo") return solveBatchFgo(problem, FgoOptions{});
  if (estimator == "fgo-window") return solveWindowFgo(problem, FgoOptions{});
  return runEkf(problem, EkfOptions{});
}

TEST(StreamedNavigate, CommandWritesTheInMemorySolution) {
  const EstimationProblem problem = sampleProblem();
  for (const char* est : {"ekf", "rts", "fgo-window", "fgo"}) {
    const std::string dir = test::makeTempDir(std::string("streamed_navigate_") + est);
    const std::string cmd = test::graftnavBinary() + " navigate " + sampleDir() +
                            " --imu tested --estimator " + est +
                            " --outage-length 60 --outage-period 180 --no-plots --out " + dir +
                            " > " + dir + "/log.txt 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir + "/log.txt");
    EXPECT_NE(slurp(dir + "/log.txt").find("streaming the tested IMU"), std::string::npos)
        << slurp(dir + "/log.txt");
    const NavSolution memory = inMemorySolution(est, problem);
    writeNav(dir + "/memory.nav", memory.states);
    EXPECT_TRUE(slurp(dir + "/memory.nav") == slurp(dir + "/solution.nav")) << est;
    // The command evaluated the solution against truth.nav as it came (the truth read as a
    // stream): its files equal the in-memory evaluation's, byte for byte.
    const Evaluation ev = evaluateSolution(memory, readNav(CasePaths(sampleDir()).truthNav()),
                                           problem.outages, EvaluationOptions{});
    const nlohmann::json j = nlohmann::json::parse(slurp(dir + "/errors.json"));
    const ReportMeta meta{j.at("estimator").get<std::string>(), j.at("imu").get<std::string>(),
                          j.at("outages").at("count").get<int>(),
                          j.at("outages").at("length_s").get<double>()};
    writeErrorsJson(dir + "/memory_errors.json", meta, ev);
    writeErrorsCsv(dir + "/memory_errors.csv", ev, 1.0 / 10.0);
    writeOutageCsv(dir + "/memory_outage_drift.csv", ev);
    EXPECT_TRUE(slurp(dir + "/memory_errors.json") == slurp(dir + "/errors.json")) << est;
    EXPECT_TRUE(slurp(dir + "/memory_errors.csv") == slurp(dir + "/errors.csv")) << est;
    EXPECT_TRUE(slurp(dir + "/memory_outage_drift.csv") == slurp(dir + "/outage_drift.csv")) << est;
  }
}

}  // namespace
}  // namespace graftnav
