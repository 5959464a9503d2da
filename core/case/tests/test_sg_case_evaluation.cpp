// The SG evaluation of a case folder with an estimator registry of the test's own: every solution
// (K realizations of SG#1 and of SG#2, and REAL) is navigated once by the registry's estimator
// and evaluated against SOL_REF, and the files of the run are written before the report returns.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>

#include "graftnav/case/sg_case_evaluation.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr double kNorthOffset_m = 2.0;

// An "estimator" that returns the case's truth over the problem's IMU span, moved 2 m north:
// every solution's outage error is then 2 m horizontal and 0 vertical, whatever was grafted.
EstimatorRegistry offsetTruthRegistry(const NavSeries& truth, std::atomic<int>* calls) {
  EstimatorRegistry r;
  r.add({"ekf",
         "truth moved north",
         [&truth, calls](const EstimationProblem& p, const EstimatorOptions&, const ProgressFn&) {
           ++*calls;
           NavSolution s;
           s.estimator = "ekf";
           const double dlat_rad = kNorthOffset_m / 6.36e6;  // about 2 m at the samples' latitude
           for (NavState st : truth) {
             if (st.t_s < p.imu.front().t_s || st.t_s > p.imu.back().t_s) continue;
             st.pos.lat_rad += dlat_rad;
             s.states.push_back(st);
           }
           return s;
         },
         {}});
  return r;
}

TEST(SgCaseEvaluation, NavigatesEveryRealizationAndRealOnceWithTheRegistrysEstimator) {
  const std::string case_dir = test::sourceDir() + "/data/sample_tactical";
  const CaseInputs c = loadCaseInputs(case_dir);
  std::atomic<int> calls{0};
  const EstimatorRegistry reg = offsetTruthRegistry(c.reference, &calls);

  const std::string dir = test::makeTempDir("sg_case");
  std::ofstream(dir + "/run.yaml") << "outages: {length_s: 60, period_s: 100, start_s: 60}\n"
                                      "grafting: {realizations: 2}\n";
  SgCaseEvaluationOptions o;
  o.case_dir = case_dir;
  o.out_dir = dir + "/out";
  o.run_config = dir + "/run.yaml";
  o.jobs = 1;
  const SgCaseEvaluation ev = runSgCaseEvaluation(o, reg);

  EXPECT_EQ(calls.load(), 2 * 2 + 1);   // K = 2 per strategy, and REAL
  EXPECT_FALSE(ev.errors_csv_written);  // no streamed form: the held path
  for (const char* label : {"SG1", "SG2", "REAL"}) {
    const SgSolutionErrors* s = ev.report.find(label);
    ASSERT_NE(s, nullptr) << label;
    EXPECT_NEAR(s->err_rms.horizontal_m, kNorthOffset_m, 0.02 * kNorthOffset_m) << label;
    EXPECT_NEAR(s->err_rms.vertical_m, 0.0, 1e-6) << label;
  }
  EXPECT_EQ(ev.report.find("SG1")->draws.size(), 2u);
  EXPECT_TRUE(fs::exists(o.out_dir + "/calibration.yaml"));
  EXPECT_TRUE(fs::exists(o.out_dir + "/IMU_SG1.txt"));
  EXPECT_TRUE(fs::exists(o.out_dir + "/IMU_SG2.txt"));
}

TEST(SgCaseEvaluation, UnknownEstimatorIsRefusedBeforeAnythingIsWritten) {
  const CaseInputs c = loadCaseInputs(test::sourceDir() + "/data/sample_tactical");
  std::atomic<int> calls{0};
  const EstimatorRegistry reg = offsetTruthRegistry(c.reference, &calls);
  SgCaseEvaluationOptions o;
  o.case_dir = test::sourceDir() + "/data/sample_tactical";
  o.out_dir = test::makeTempDir("sg_case_unknown") + "/out";
  o.estimator = "kalmanish";
  const std::string message = test::errorOf([&] { runSgCaseEvaluation(o, reg); });
  EXPECT_THAT(message, HasSubstr("estimator 'kalmanish': unknown (known: ekf)"));
  EXPECT_FALSE(fs::exists(o.out_dir));
  EXPECT_EQ(calls.load(), 0);
}

}  // namespace
}  // namespace graftnav
