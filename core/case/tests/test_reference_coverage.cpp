// The reference coverage check from epochs read one at a time (a streamed reference) gives the
// same errors and warnings as the check on the series held whole, and the rate kAuto compares.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/input_checks.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

NavSeries epochs(double t0, double t1, double dt) {
  NavSeries s;
  for (double t = t0; t <= t1 + 1e-9; t += dt) {
    NavState x;
    x.t_s = t;
    s.push_back(x);
  }
  return s;
}

ImuSeries imuSpan(double t0, double t1) {
  ImuSample a, b;
  a.t_s = t0 + 0.005;
  a.dt_s = 0.005;
  b.t_s = t1;
  b.dt_s = 0.005;
  return {a, b};
}

// Both forms: the held check's message, or "" when it passes (then its warnings must match).
std::string heldOutcome(const NavSeries& ref, const ImuSeries& imu,
                        const std::vector<TimeWindow>& outages, std::vector<std::string>* w) {
  try {
    *w = checkReferenceCoverage(ref, "truth.nav", imu, outages);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}
std::string streamedOutcome(const NavSeries& ref, const ImuSeries& imu,
                            const std::vector<TimeWindow>& outages, std::vector<std::string>* w) {
  ReferenceCoverage c(outages);
  for (const NavState& s : ref) c.add(s.t_s);
  try {
    *w = c.check("truth.nav", imu);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ReferenceCoverage, SameOutcomeAsTheHeldSeries) {
  const ImuSeries imu = imuSpan(0.0, 1000.0);
  NavSeries gap = epochs(0.0, 300.0, 0.1);  // a gap from 300 to 500 s
  const NavSeries after = epochs(500.0, 1000.0, 0.1);
  gap.insert(gap.end(), after.begin(), after.end());
  struct Case {
    NavSeries ref;
    std::vector<TimeWindow> outages;
    bool throws;
    bool warns;
  };
  const std::vector<Case> cases = {
      {epochs(0.0, 1000.0, 0.1), {{100, 160}, {280, 340}, {940, 1000}}, false, false},
      // outages out of start order, one inside the gap
      {gap, {{600, 660}, {350, 410}}, true, false},
      // a window overlapping the gap's edge is covered
      {gap, {{250, 310}, {480, 540}}, false, false},
      // a reference ending before the IMU: covered outages, a warning
      {epochs(0.0, 700.0, 0.1), {{100, 160}, {640, 700}}, false, true},
      // an outage past the reference's end
      {epochs(0.0, 700.0, 0.1), {{100, 160}, {750, 810}}, true, true},
      // overlapping windows, a long one and a short one inside it
      {epochs(0.0, 1000.0, 5.0), {{100, 400}, {151, 154}}, true, false},
      {epochs(0.0, 1000.0, 5.0), {{100, 400}, {150, 156}}, false, false},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    std::vector<std::string> wa, wb;
    const std::string a = heldOutcome(c.ref, imu, c.outages, &wa);
    const std::string b = streamedOutcome(c.ref, imu, c.outages, &wb);
    EXPECT_EQ(a, b) << "case " << i;
    EXPECT_EQ(wa, wb) << "case " << i;
    EXPECT_EQ(!a.empty(), c.throws) << "case " << i << ": " << a;
    if (!c.throws) {
      EXPECT_EQ(!wa.empty(), c.warns) << "case " << i;
    }
  }
  std::vector<std::string> w;
  EXPECT_THAT(streamedOutcome(gap, imu, {{350, 410}}, &w),
              HasSubstr("no reference epoch inside the outage [350.000, 410.000] s"));
}

TEST(ReferenceCoverage, RateAsTheEvaluationComparesIt) {
  ReferenceCoverage c({});
  EXPECT_EQ(c.rateHz(), 0.0);
  for (const NavState& s : epochs(10.0, 20.0, 0.005)) c.add(s.t_s);
  EXPECT_EQ(c.count(), 2001);
  EXPECT_NEAR(c.rateHz(), 200.0, 1e-6);
  EXPECT_DOUBLE_EQ(c.firstTime(), 10.0);
}

TEST(CaseReferenceFile, TruthFoundWithoutReadingIt) {
  CaseLoadOptions o;
  o.load_reference = false;
  const CaseInputs c = loadCaseInputs(test::sourceDir() + "/data/sample_tactical", o);
  EXPECT_TRUE(c.reference.empty());
  const CaseReferenceFile f = caseReferenceFile(c, false);
  EXPECT_TRUE(f.is_truth);
  EXPECT_EQ(f.path, c.paths().truthNav());
}

}  // namespace
}  // namespace graftnav
