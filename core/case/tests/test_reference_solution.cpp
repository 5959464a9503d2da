// SOL_REF: the case's truth when it has one, else the reference IMU smoothed by the registry's
// smoother on the problem of the case (started at the initial state when asked).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "graftnav/case/reference_solution.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

// A smoother that records the problem it was given and returns its IMU epochs as states.
struct FakeSmoother {
  int calls = 0;
  std::size_t imu_samples = 0;
  EstimatorRegistry registry() {
    EstimatorRegistry r;
    r.add({"rts",
           "fake",
           [this](const EstimationProblem& p, const EstimatorOptions&, const ProgressFn&) {
             ++calls;
             imu_samples = p.imu.size();
             NavSolution s;
             NavState st = p.initial;
             st.t_s = p.imu.back().t_s;
             s.states = {p.initial, st};
             return s;
           },
           {}});
    return r;
  }
};

TEST(ReferenceSolution, TruthWhenTheCaseHasItElseTheSmoothedReferenceImu) {
  const CaseInputs c = loadCaseInputs(test::sourceDir() + "/data/sample_tactical");
  FakeSmoother fake;
  const EstimatorRegistry reg = fake.registry();
  int loads = 0;
  const ReferenceImuFn ref = [&] {
    ++loads;
    return selectImu(c, "ref");
  };
  const ReferenceSolution truth = resolveReferenceSolution(c, ref, RunConfig{}, reg);
  EXPECT_FALSE(truth.smoothed);
  EXPECT_EQ(truth.states.size(), c.reference.size());
  EXPECT_THAT(truth.description, HasSubstr("truth ("));
  EXPECT_EQ(loads, 0);  // the reference IMU is not read when it is not smoothed
  EXPECT_EQ(fake.calls, 0);

  ReferenceSolutionOptions smooth;
  smooth.use_case_reference = false;
  const ReferenceSolution s = resolveReferenceSolution(c, ref, RunConfig{}, reg, smooth);
  EXPECT_TRUE(s.smoothed);
  EXPECT_EQ(fake.calls, 1);
  EXPECT_EQ(loads, 1);
  EXPECT_EQ(s.states.size(), 2u);
  EXPECT_THAT(s.description, HasSubstr("RTS-smoothed reference IMU with all GNSS"));

  ImuSelection no_noise = selectImu(c, "ref");
  no_noise.profile_given = false;
  try {
    resolveReferenceSolution(
        c, [&] { return no_noise; }, RunConfig{}, reg, smooth);
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("case.yaml: reference_imu needs noise parameters"));
  }
}

}  // namespace
}  // namespace graftnav
