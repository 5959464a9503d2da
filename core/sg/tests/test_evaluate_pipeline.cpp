// The evaluate pipeline with an injected navigator: every unit is navigated once per schedule,
// the report holds K draws per strategy and REAL, the outcome does not depend on the number of
// threads, and bad options or schedules fail before any navigation.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "graftnav/sg/evaluate_pipeline.h"

namespace graftnav {
namespace {

constexpr double kT0 = 1000.0, kDt = 0.1, kSpan = 600.0;

BasicErrorSignal labRecord() {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 1e-3);
  ImuSeries s;
  for (int k = 1; k <= 2000; ++k) {
    ImuSample x;
    x.dt_s = kDt;
    x.t_s = k * kDt;
    x.dtheta_rad = Eigen::Vector3d(g(rng), g(rng), g(rng)) * kDt;
    x.dvel_m_s = Eigen::Vector3d(g(rng), g(rng), g(rng)) * kDt;
    s.push_back(x);
  }
  return BasicErrorSignal(s);
}

SgEvaluationInputs inputs() {
  SgEvaluationInputs in;
  in.case_name = "/cases/fake";
  for (int k = 1; k <= static_cast<int>(kSpan / kDt); ++k) {
    ImuSample s;
    s.dt_s = kDt;
    s.t_s = kT0 + k * kDt;
    in.reference_imu.push_back(s);
  }
  in.tested_profile.gyro_bias_instability_rad_s = 2e-5;
  in.tested_profile.accel_bias_instability_m_s2 = 3e-3;
  in.tested_profile.gyro_bias_repeatability_rad_s = 1e-4;
  in.tested_profile.accel_bias_repeatability_m_s2 = 1e-2;
  in.has_real = true;
  in.real_imu_file = "tested_imu.txt";
  in.outages.length_s = 30.0;
  in.outages.period_s = 100.0;
  in.outages.start_s = 100.0;
  in.notes = {"lab note"};
  return in;
}

GraftPlan plan() { return GraftPlan{labRecord(), SensorDynamicFit{}, SensorDynamicFit{}}; }

NavSeries reference() {
  NavSeries r;
  for (int k = 0; k <= static_cast<int>(kSpan); ++k) {
    NavState s;
    s.t_s = kT0 + k;
    s.pos.lat_rad = 0.5;
    s.pos.lon_rad = 2.0;
    r.push_back(s);
  }
  return r;
}

// A stand-in estimator: the reference displaced north by 1 m for REAL and by 1 m plus a
// multiple of the grafted series' summed gyro increments for SG (each realization differs).
SgNavigator fakeNavigator(std::atomic<int>* calls) {
  return [calls](std::optional<ImuSeries> grafted, const OutageScheduleConfig& schedule) {
    ++*calls;
    double north_m = 1.0;
    if (grafted) {
      double sum = 0.0;
      for (const auto& s : *grafted) sum += s.dtheta_rad.x();
      north_m += 1e3 * std::abs(sum);
    }
    SgNavigation nav;
    nav.solution.states = reference();
    for (auto& s : nav.solution.states) s.pos.lat_rad += north_m / 6.36e6;
    nav.outages = buildOutageWindows(schedule, kT0, kT0 + kSpan);
    nav.notes = {grafted ? "grafted" : "real"};
    return nav;
  };
}

TEST(EvaluatePipeline, EveryUnitOnceKDrawsPerStrategyAndRealFirstInTheNotes) {
  SgEvaluationOptions o;
  o.realizations = 5;
  o.outage_shifts = 2;
  const SgEvaluationPipeline p(o, plan(), inputs());
  ASSERT_EQ(p.schedules().size(), 2u);
  EXPECT_DOUBLE_EQ(p.schedules()[1].start_s, 150.0);
  std::atomic<int> calls{0};
  const SgEvaluationReport r = p.run({reference(), "fake truth"}, fakeNavigator(&calls), "fake");
  EXPECT_EQ(calls.load(), 2 * (2 * 5 + 1));
  ASSERT_EQ(r.solutions.size(), 3u);
  EXPECT_EQ(r.solutions[0].label, "SG1");
  EXPECT_EQ(r.solutions[1].label, "SG2");
  EXPECT_EQ(r.solutions[2].label, "REAL");
  EXPECT_EQ(r.solutions[0].draws.size(), 5u);
  EXPECT_TRUE(r.solutions[2].draws.empty());
  EXPECT_NEAR(r.find("REAL")->err_rms.horizontal_m, 1.0, 0.01);
  EXPECT_GT(r.find("SG1")->err_rms.horizontal_m, 1.0);
  EXPECT_NE(r.solutions[0].draws[0].horizontal_m, r.solutions[0].draws[1].horizontal_m);
  EXPECT_EQ(r.reference, "fake truth");
  EXPECT_EQ(r.estimator, "fake");
  EXPECT_EQ(r.outages.size(), 5u);
  EXPECT_EQ(r.notes.front(), "lab note");
  EXPECT_EQ(r.notes.back(), "real");  // the first unit's notes close the list
  EXPECT_TRUE(r.find("SG2")->predictive.real_valid[0]);
}

TEST(EvaluatePipeline, TheOutcomeDoesNotDependOnTheThreads) {
  SgEvaluationOptions o;
  o.realizations = 4;
  o.strategies = {SgStrategy::kBasic};
  std::atomic<int> calls{0};
  o.jobs = 1;
  const SgEvaluationReport a = SgEvaluationPipeline(o, plan(), inputs())
                                   .run({reference(), "r"}, fakeNavigator(&calls), "fake");
  o.jobs = 3;
  const SgEvaluationReport b = SgEvaluationPipeline(o, plan(), inputs())
                                   .run({reference(), "r"}, fakeNavigator(&calls), "fake");
  ASSERT_EQ(a.solutions.size(), 2u);  // SG1 and REAL only
  for (std::size_t k = 0; k < a.solutions[0].draws.size(); ++k)
    EXPECT_EQ(a.solutions[0].draws[k].horizontal_m, b.solutions[0].draws[k].horizontal_m);
  EXPECT_EQ(calls.load(), 2 * (4 + 1));
}

TEST(EvaluatePipeline, BadOptionsAndSchedulesFailBeforeAnyNavigation) {
  SgEvaluationOptions o;
  o.realizations = 0;
  // The library names its option fields, not a command's flags (the commands check their flags).
  try {
    SgEvaluationPipeline p(o, plan(), inputs());
    FAIL() << "realizations 0 must throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("SgEvaluationOptions.realizations"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
  o = SgEvaluationOptions{};
  o.outage_shifts = 2;
  SgEvaluationInputs in = inputs();
  in.outages.explicit_windows = {{kT0 + 100.0, kT0 + 130.0}};
  EXPECT_THROW(SgEvaluationPipeline(o, plan(), in), std::invalid_argument);
  o = SgEvaluationOptions{};
  in = inputs();
  in.outages.start_s = 700.0;  // after the data
  try {
    SgEvaluationPipeline p(o, plan(), in);
    FAIL() << "no outage inside the data must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/cases/fake"), std::string::npos) << e.what();
  }
  std::atomic<int> calls{0};
  SgNavigator failing = [&calls](std::optional<ImuSeries>,
                                 const OutageScheduleConfig&) -> SgNavigation {
    ++calls;
    throw std::runtime_error("estimator diverged");
  };
  o.realizations = 3;
  o.jobs = 1;
  EXPECT_THROW(SgEvaluationPipeline(o, plan(), inputs()).run({reference(), "r"}, failing, "x"),
               std::runtime_error);
  EXPECT_EQ(calls.load(), 1);  // the first failure stops the workers
}

}  // namespace
}  // namespace graftnav
