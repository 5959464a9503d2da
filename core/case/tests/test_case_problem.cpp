// A bundled sample case loaded as every command loads it, and the estimator inputs made from it:
// initial state from the truth, the outage schedule counted from the first IMU epoch, the time
// range cut, the problem started at the initial state's epoch, and the errors that name files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/problem.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

std::string sample() { return test::sourceDir() + "/data/sample_tactical"; }

TEST(CaseInputs, SampleLoadsWithTruthGnssAndBothImus) {
  const CaseInputs c = loadCaseInputs(sample());
  EXPECT_FALSE(c.gnss.empty());
  EXPECT_TRUE(c.reference_is_truth);
  EXPECT_THAT(c.reference_name, HasSubstr("field/truth.nav"));
  const ImuSelection ref = selectImu(c, "ref");
  const ImuSelection tested = selectImu(c, "tested");
  EXPECT_TRUE(ref.profile_given);
  EXPECT_EQ(ref.imu.size(), tested.imu.size());
  EXPECT_EQ(tested.label, c.config.tested_imu->name);
  const ImuSelection unread = selectImu(c, "tested", "", false, false);
  EXPECT_TRUE(unread.imu.empty());
  EXPECT_EQ(unread.read_options.nominal_rate_hz, c.config.testedImuRateHz());
}

// No --imu: the reference IMU, else the case's only IMU (a real recording of one IMU), said in a
// note; an explicit choice is kept as given.
TEST(CaseInputs, DefaultImuIsTheReferenceElseTheOnlyOne) {
  const std::string dir = test::makeTempDir("default_imu");
  const CasePaths paths(dir);
  std::filesystem::create_directories(dir + "/field");
  std::string note;
  EXPECT_EQ(chooseImu("", paths, &note), "ref");  // neither: selectImu names the missing file
  std::ofstream(paths.testedImu()) << "1 0 0 0 0 0 0\n";
  EXPECT_EQ(chooseImu("", paths, &note), "tested");
  EXPECT_THAT(note, HasSubstr("'tested'"));
  EXPECT_THAT(note, HasSubstr("field/tested_imu.txt"));
  note.clear();
  EXPECT_EQ(chooseImu("ref", paths, &note), "ref");
  EXPECT_TRUE(note.empty());
  std::ofstream(paths.refImu()) << "1 0 0 0 0 0 0\n";
  EXPECT_EQ(chooseImu("", paths, &note), "ref");
  EXPECT_TRUE(note.empty());
  EXPECT_EQ(chooseImu("tested", paths, &note), "tested");
}

TEST(CaseInputs, ErrorsNameTheDirectoryOrFile) {
  try {
    loadCaseInputs(sample() + "/field");
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("is not a case directory: no case.yaml"));
  }
  const CaseInputs c = loadCaseInputs(sample());
  try {
    selectImu(c, sample() + "/field/missing.txt");
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("missing.txt' not found"));
  }
}

TEST(Problem, InitialStateFromTruthAndOutagesFromTheFirstImuEpoch) {
  const CaseInputs c = loadCaseInputs(sample());
  const ImuSelection tested = selectImu(c, "tested");
  OutageOverrides ov;
  ov.length_s = 30.0;
  ov.start_s = 100.0;
  std::vector<std::string> notes;
  const EstimationProblem p =
      makeProblem(c, tested, RunConfig{}, ov.appliedTo(OutageScheduleConfig{}), &notes);
  const double t0 = tested.imu.front().t_s - tested.imu.front().dt_s;
  EXPECT_NEAR(p.initial.t_s, std::max(t0, c.reference.front().t_s), 1e-3);
  ASSERT_FALSE(p.outages.empty());
  EXPECT_NEAR(p.outages.front().start_s, t0 + 100.0, 1e-9);
  EXPECT_NEAR(p.outages.front().length_s(), 30.0, 1e-9);
  EXPECT_EQ(p.imu.size(), tested.imu.size());
  EXPECT_EQ(p.lever_arm_b_m, *c.config.lever_arm_m);
  EXPECT_THAT(notes.front(), HasSubstr("initial state from truth.nav"));
  EXPECT_NO_THROW(
      requireOutagesInsideData(OutageScheduleConfig{}, p.outages, t0, p.imu.back().t_s));
}

TEST(Problem, TimeRangeAndStartAtTheInitialState) {
  CaseInputs c = loadCaseInputs(sample());
  ImuSelection imu = selectImu(c, "ref");
  const double t0 = imu.imu.front().t_s;
  TimeRangeConfig range;
  range.start_s = t0 + 60.0;
  range.end_s = t0 + 200.0;
  std::vector<std::string> notes;
  restrictToTimeRange(range, &c, &imu, &notes);
  EXPECT_GE(imu.imu.front().t_s - imu.imu.front().dt_s, *range.start_s - 1e-6);
  EXPECT_LE(imu.imu.back().t_s, *range.end_s);
  EXPECT_THAT(notes.back(), HasSubstr("time range"));
  for (const auto& f : c.gnss) EXPECT_TRUE(f.t_s >= *range.start_s && f.t_s <= *range.end_s);

  EstimationProblem p = makeProblem(c, imu, RunConfig{}, std::nullopt, &notes);
  p.initial.t_s += 10.0;  // as after an alignment that took 10 s
  const std::size_t n = p.imu.size();
  startAtInitialState(&p, &notes);
  EXPECT_LT(p.imu.size(), n);
  EXPECT_GE(p.imu.front().t_s - p.imu.front().dt_s, p.initial.t_s - 1e-6);
  EXPECT_GT(p.gnss.front().t_s, p.initial.t_s);
  EXPECT_THAT(notes.back(), HasSubstr("GNSS epochs before the initial state epoch not used"));

  range.start_s = t0 + 1e7;
  range.end_s = t0 + 2e7;
  EXPECT_THROW(restrictToTimeRange(range, &c, &imu, &notes), std::runtime_error);
}

TEST(OutageOverrides, GivenValuesOverTheConfigTheRestKept) {
  OutageScheduleConfig base;
  base.length_s = 20.0;
  base.end_margin_s = 3.0;
  OutageOverrides ov;
  EXPECT_FALSE(ov.any());
  ov.period_s = 90.0;
  const OutageScheduleConfig s = ov.appliedTo(base);
  EXPECT_TRUE(ov.any());
  EXPECT_EQ(s.length_s, 20.0);
  EXPECT_EQ(s.period_s, 90.0);
  EXPECT_EQ(s.end_margin_s, 3.0);
  ov.length_s = 100.0;
  EXPECT_THROW(ov.validate(), std::runtime_error);  // period shorter than the length
  ov.length_s = -1.0;
  EXPECT_THROW(ov.validate(), std::runtime_error);
  OutageOverrides start;
  start.start_s = -5.0;
  EXPECT_THROW(start.validate(), std::runtime_error);
}

TEST(InputChecks, GnssCoverageAndLabRecordFloors) {
  const CaseInputs c = loadCaseInputs(sample());
  const ImuSelection ref = selectImu(c, "ref");
  EXPECT_TRUE(checkGnssCoverage(c.gnss, "gnss.pos", ref.imu, false).empty());
  EXPECT_THROW(checkGnssCoverage(GnssSeries{}, "gnss.pos", ref.imu, false), std::runtime_error);
  EXPECT_EQ(checkGnssCoverage(GnssSeries{}, "gnss.pos", ref.imu, true).size(), 1u);
  EXPECT_THROW(checkLabStaticRecord(0.1, "static.txt", 0.0), std::runtime_error);
  EXPECT_EQ(checkLabStaticRecord(100.0, "static.txt", 180.0).size(), 1u);
  EXPECT_TRUE(checkLabStaticRecord(600.0, "static.txt", 180.0).empty());
}

}  // namespace
}  // namespace graftnav
