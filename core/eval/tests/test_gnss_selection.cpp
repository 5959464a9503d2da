#include <gtest/gtest.h>

#include <cmath>

#include "graftnav/eval/gnss_selection.h"

namespace graftnav {
namespace {

GnssFix fix(double t, int type, double std_h, double std_v) {
  GnssFix f;
  f.t_s = t;
  f.pos = Geodetic{0.7, 2.0, 50.0};
  f.std_ned_m = Eigen::Vector3d(std_h, std_h, std_v);
  f.fix_type = type;
  return f;
}

TEST(GnssSelection, CountsEveryEpochUnderOneReason) {
  GnssSeries g;
  for (int i = 0; i < 10; ++i) g.push_back(fix(100.0 + 0.1 * i, 1, 2.0, 9.0));  // single point
  for (int i = 0; i < 3; ++i) g.push_back(fix(101.05 + i, 4, 0.01, 0.02));      // RTK fixed
  g.push_back(fix(104.5, 5, 0.2, 0.3));                                         // RTK float
  g.push_back(fix(104.6, 4, 0.5, 0.3));                                         // fixed, bad std
  g.push_back(fix(104.7, 4, std::nan(""), 0.1));                                // non-finite
  GnssSelectionOptions o;
  o.accepted_fix_types = {4, 5};
  o.max_horizontal_std_m = 0.3;
  const GnssSelection s = selectGnss(g, o);
  EXPECT_EQ(s.counts.input, 16);
  EXPECT_EQ(s.counts.used, 4);
  EXPECT_EQ(s.counts.rejected_fix_type, 10);
  EXPECT_EQ(s.counts.rejected_std, 1);
  EXPECT_EQ(s.counts.rejected_non_finite, 1);
  EXPECT_EQ(s.counts.used + s.counts.rejected(), s.counts.input);
  EXPECT_EQ(s.counts.used_by_fix_type.at(4), 3);
  EXPECT_EQ(s.counts.used_by_fix_type.at(5), 1);
  EXPECT_EQ(s.counts.input_by_fix_type.at(1), 10);
  EXPECT_NE(s.counts.summary().find("used 4"), std::string::npos);
}

TEST(GnssSelection, LatencyPerFixTypeShiftsAndResorts) {
  GnssSeries g = {fix(10.0, 1, 2, 9), fix(10.1, 4, 0.01, 0.01), fix(10.2, 1, 2, 9),
                  fix(10.3, 1, 2, 9)};
  GnssSelectionOptions o;
  o.latency_s_by_fix_type[4] = 0.4;  // the RTK fix was measured at 9.7
  const GnssSelection s = selectGnss(g, o);
  ASSERT_EQ(s.counts.used, 4);
  EXPECT_EQ(s.kept.front().fix_type, 4);
  EXPECT_NEAR(s.kept.front().t_s, 9.7, 1e-12);
  EXPECT_GT(s.counts.reordered, 0);
  for (std::size_t i = 1; i < s.kept.size(); ++i) EXPECT_LT(s.kept[i - 1].t_s, s.kept[i].t_s);
}

TEST(GnssSelection, CollidingTimesAfterCorrectionAreCountedNotSilent) {
  GnssSeries g = {fix(10.0, 1, 2, 9), fix(10.5, 4, 0.01, 0.01)};
  GnssSelectionOptions o;
  o.latency_s_by_fix_type[4] = 0.5;
  const GnssSelection s = selectGnss(g, o);
  EXPECT_EQ(s.counts.used, 1);
  EXPECT_EQ(s.counts.rejected_duplicate_time, 1);
  EXPECT_EQ(s.counts.used + s.counts.rejected(), s.counts.input);
}

TEST(GnssSelection, MinSpacingKeepsTheMorePreciseEpoch) {
  GnssSeries g = {fix(10.0, 1, 2, 9), fix(10.01, 4, 0.01, 0.01), fix(10.1, 1, 2, 9),
                  fix(10.2, 1, 2, 9), fix(10.22, 1, 3, 9)};
  GnssSelectionOptions o;
  o.min_spacing_s = 0.05;
  const GnssSelection s = selectGnss(g, o);
  ASSERT_EQ(s.counts.used, 3);
  EXPECT_EQ(s.counts.rejected_spacing, 2);
  EXPECT_EQ(s.kept[0].fix_type, 4);         // the RTK epoch replaced the single-point one
  EXPECT_NEAR(s.kept[2].t_s, 10.2, 1e-12);  // the noisier 10.22 epoch was dropped
  EXPECT_EQ(s.counts.used + s.counts.rejected(), s.counts.input);
}

TEST(GnssSelection, ValidateNamesTheField) {
  GnssSelectionOptions o;
  o.max_horizontal_std_m = 0.0;
  try {
    o.validate();
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_horizontal_std_m"), std::string::npos);
  }
  GnssSelectionOptions l;
  l.latency_s_by_fix_type[4] = 99.0;
  EXPECT_THROW(l.validate(), std::invalid_argument);
  EXPECT_TRUE(GnssSelectionOptions{}.isIdentity());
}

}  // namespace
}  // namespace graftnav
