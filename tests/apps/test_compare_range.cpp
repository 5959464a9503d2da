// compare with a time range (the run config's, or the request's bounds over it) against navigate
// with the same range: each estimator's solution, epoch by epoch, and its errors against the
// reference, number by number, streamed and in memory; a range that keeps no sample fails as
// navigate's does.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/estimation/solution_sink.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/navigate/compare_run.h"
#include "graftnav/navigate/navigate_run.h"
#include "graftnav/navigate/navigate_setup.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

using Recorded = std::map<std::string, NavSeries>;  // the states of each run, by estimator

// Passes every epoch on and keeps its state.
class RecordingSink final : public SolutionSink {
 public:
  RecordingSink(SolutionSink* next, NavSeries* states) : next_(next), states_(states) {}
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate& e) override {
    states_->push_back(state);
    next_->add(state, sigma, e);
  }
  void addOdometerScale(const OdometerScaleEstimate& s) override { next_->addOdometerScale(s); }

 private:
  SolutionSink* next_;
  NavSeries* states_;
};

// The estimator table whose runs record their states into *recorded; without the streamed forms
// when `streamed` is false (every run then holds its series).
EstimatorRegistry recordingTable(bool streamed, std::shared_ptr<Recorded> recorded) {
  EstimatorRegistry r;
  for (EstimatorEntry e : estimatorTable().entries()) {
    const std::string name = e.name;
    const EstimatorFn run = e.run;
    e.run = [run, recorded, name](const EstimationProblem& p, const EstimatorOptions& o,
                                  const ProgressFn& progress) {
      NavSolution sol = run(p, o, progress);
      (*recorded)[name] = sol.states;
      return sol;
    };
    const StreamingEstimatorFn stream = e.stream;
    if (!streamed || !stream) {
      e.stream = {};
    } else {
      e.stream = [stream, recorded, name](const EstimationProblem& p, const ImuPassFn& imu,
                                          const EstimatorOptions& o, SolutionSink& sink) {
        NavSeries& states = (*recorded)[name];
        states.clear();
        RecordingSink tee(&sink, &states);
        return stream(p, imu, o, tee);
      };
    }
    r.add(e);
  }
  return r;
}

void expectSameStats(const DriftStats& a, const DriftStats& b, const std::string& what) {
  EXPECT_EQ(a.horizontal_m, b.horizontal_m) << what;
  EXPECT_EQ(a.vertical_m, b.vertical_m) << what;
  EXPECT_EQ(a.roll_rad, b.roll_rad) << what;
  EXPECT_EQ(a.pitch_rad, b.pitch_rad) << what;
  EXPECT_EQ(a.heading_rad, b.heading_rad) << what;
}

void expectSameEvaluation(const Evaluation& c, const Evaluation& n, const std::string& name) {
  EXPECT_EQ(c.epoch_count, n.epoch_count) << name;
  EXPECT_EQ(c.outage_epochs, n.outage_epochs) << name;
  expectSameStats(c.overall_rms, n.overall_rms, name + " overall");
  expectSameStats(c.outage_rms, n.outage_rms, name + " outage RMS");
  expectSameStats(c.outage_max_rms, n.outage_max_rms, name + " outage max RMS");
  ASSERT_EQ(c.outages.size(), n.outages.size()) << name;
  for (std::size_t k = 0; k < c.outages.size(); ++k) {
    EXPECT_EQ(c.outages[k].window.start_s, n.outages[k].window.start_s) << name;
    EXPECT_EQ(c.outages[k].epochs, n.outages[k].epochs) << name;
    expectSameStats(c.outages[k].max, n.outages[k].max, name + " outage " + std::to_string(k));
  }
}

// Every state of the two runs equal (time, position, velocity, attitude).
void expectSameStates(const NavSeries& c, const NavSeries& n, const std::string& name) {
  ASSERT_EQ(c.size(), n.size()) << name;
  int differ = 0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const bool same = c[k].t_s == n[k].t_s && c[k].pos.lat_rad == n[k].pos.lat_rad &&
                      c[k].pos.lon_rad == n[k].pos.lon_rad && c[k].pos.h_m == n[k].pos.h_m &&
                      c[k].v_n == n[k].v_n && c[k].q_nb.coeffs() == n[k].q_nb.coeffs();
    if (!same && differ++ == 0) ADD_FAILURE() << name << ": state " << k << " differs";
  }
  EXPECT_EQ(differ, 0) << name;
}

struct RangeCase {
  std::string name;
  std::string alignment;
  double start_s, end_s;
  bool range_in_request;  // the bounds from the request (--start/--end) instead of the run config
};

std::string runConfig(const RangeCase& c, const std::string& dir) {
  const std::string path = dir + "/" + c.name + ".yaml";
  std::ofstream f(path);
  f << std::setprecision(12) << "ekf:\n  alignment: " << c.alignment
    << "\n  static_alignment_s: 25\n";
  if (!c.range_in_request)
    f << "time_range:\n  start_s: " << c.start_s << "\n  end_s: " << c.end_s << "\n";
  f << "outages:\n  length_s: 30\n  period_s: 120\n  start_s: 40\n";
  return path;
}

TimeRangeConfig requestRange(const RangeCase& c) {
  TimeRangeConfig r;
  if (c.range_in_request) {
    r.start_s = c.start_s;
    r.end_s = c.end_s;
  }
  return r;
}

class CompareRange : public ::testing::TestWithParam<RangeCase> {};

TEST_P(CompareRange, EachEstimatorEqualsNavigateWithTheSameRange) {
  const RangeCase& c = GetParam();
  const std::string dir = test::makeTempDir("compare_range_" + c.name);
  const std::string case_dir = test::sourceDir() + "/data/sample_mems";
  const std::vector<std::string> estimators{"ekf", "fgo-window"};
  for (bool streamed : {true, false}) {
    auto from_compare = std::make_shared<Recorded>();
    auto from_navigate = std::make_shared<Recorded>();
    const EstimatorRegistry compare_table = recordingTable(streamed, from_compare);
    const EstimatorRegistry navigate_table = recordingTable(streamed, from_navigate);
    CompareRequest cq;
    cq.case_dir = case_dir;
    cq.imu = "tested";
    cq.estimators = estimators;
    cq.run_config = runConfig(c, dir);
    cq.time_range = requestRange(c);
    const CompareInputs in = loadCompareInputs(cq, compare_table, RunMessages{});
    ASSERT_EQ(in.stream, streamed);
    const CompareReport report = runCompare(cq, in, compare_table);
    ASSERT_EQ(report.rows.size(), estimators.size());
    for (std::size_t k = 0; k < estimators.size(); ++k) {
      const std::string name = estimators[k] + (streamed ? " streamed" : " in memory");
      NavigateRequest nq;
      nq.case_dir = case_dir;
      nq.out_dir = dir + "/" + c.name + "_" + estimators[k] + (streamed ? "_s" : "_m");
      fs::create_directories(nq.out_dir);
      nq.imu = "tested";
      nq.estimator = estimators[k];
      nq.run_config = cq.run_config;
      nq.time_range = cq.time_range;
      const NavigateSetup s = prepareNavigate(nq, navigate_table, RunMessages{});
      ASSERT_EQ(s.stream, streamed);
      EXPECT_EQ(in.p.outages.size(), s.pr.outages.size()) << name;
      const NavigateOutcome o = runNavigate(s, nq.out_dir, navigate_table, RunMessages{});
      ASSERT_TRUE(o.evaluation.has_value());
      const NavSeries& states = (*from_compare)[estimators[k]];
      ASSERT_GT(states.size(), 1000u) << name;
      EXPECT_GE(states.front().t_s, c.start_s) << name;  // the range is applied
      EXPECT_LE(states.back().t_s, c.end_s) << name;
      EXPECT_GT(states.back().t_s, c.end_s - 0.05) << name;
      expectSameStates(states, (*from_navigate)[estimators[k]], name);
      expectSameEvaluation(report.rows[k].eval, *o.evaluation, name);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    SampleMems, CompareRange,
    ::testing::Values(
        // Levelled at rest over 25 s from the range's start; the end before the IMU's.
        RangeCase{"static_config", "static", 456430.0, 457150.0, false},
        // A start between two samples (50 Hz), the bounds from the request.
        RangeCase{"static_request", "static", 456430.013, 457100.0, true},
        // In motion from 456474 s: the alignment's epoch 44 s into the range.
        RangeCase{"motion_config", "motion", 456430.0, 457150.0, false}),
    [](const ::testing::TestParamInfo<RangeCase>& p) { return p.param.name; });

TEST(CompareRange, ARangeWithoutSamplesFailsAsNavigateFails) {
  const std::string dir = test::makeTempDir("compare_range_empty");
  const RangeCase c{"empty", "static", 100.0, 200.0, false};
  CompareRequest cq;
  cq.case_dir = test::sourceDir() + "/data/sample_mems";
  cq.imu = "tested";
  cq.estimators = {"ekf"};
  cq.run_config = runConfig(c, dir);
  NavigateRequest nq;
  nq.case_dir = cq.case_dir;
  nq.out_dir = dir + "/navigate";
  nq.imu = "tested";
  nq.run_config = cq.run_config;
  const std::string compare_error =
      test::errorOf([&] { loadCompareInputs(cq, estimatorTable(), RunMessages{}); });
  const std::string navigate_error =
      test::errorOf([&] { prepareNavigate(nq, estimatorTable(), RunMessages{}); });
  EXPECT_NE(compare_error.find("time range [100, 200] holds no sample"), std::string::npos)
      << compare_error;
  EXPECT_EQ(compare_error, navigate_error);
}

}  // namespace
}  // namespace graftnav
