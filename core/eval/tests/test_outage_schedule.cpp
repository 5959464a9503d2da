#include <gtest/gtest.h>

#include "graftnav/eval/outage_schedule.h"

namespace graftnav {
namespace {

TEST(OutageSchedule, PeriodicAfterWarmUpDropsWindowsPastTheEnd) {
  OutageScheduleConfig cfg;  // 60 s every 180 s from 300 s, 10 s end margin
  const auto w = buildOutageWindows(cfg, 1000.0, 2000.0);
  ASSERT_EQ(w.size(), 4u);  // starts 1300, 1480, 1660, 1840; 2020 would end past 1990
  EXPECT_DOUBLE_EQ(w[0].start_s, 1300.0);
  EXPECT_DOUBLE_EQ(w[0].end_s, 1360.0);
  EXPECT_DOUBLE_EQ(w[3].start_s, 1840.0);
  EXPECT_DOUBLE_EQ(w[3].end_s, 1900.0);
  for (const auto& x : w) EXPECT_DOUBLE_EQ(x.length_s(), 60.0);
}

TEST(OutageSchedule, OutageAtStartAndExactlyAtEndMargin) {
  OutageScheduleConfig cfg;
  cfg.start_s = 0.0;
  cfg.length_s = 50.0;
  cfg.period_s = 100.0;
  cfg.end_margin_s = 0.0;
  const auto w = buildOutageWindows(cfg, 0.0, 250.0);
  ASSERT_EQ(w.size(), 3u);  // [0,50], [100,150], [200,250] ends exactly at the data end: kept
  EXPECT_DOUBLE_EQ(w[0].start_s, 0.0);
  EXPECT_DOUBLE_EQ(w[2].end_s, 250.0);
  cfg.end_margin_s = 1.0;  // now the last one ends inside the margin: dropped, never clipped
  EXPECT_EQ(buildOutageWindows(cfg, 0.0, 250.0).size(), 2u);
}

TEST(OutageSchedule, ScheduleLongerThanDataGivesNoWindow) {
  OutageScheduleConfig cfg;
  EXPECT_TRUE(buildOutageWindows(cfg, 0.0, 200.0).empty());
  cfg.enabled = false;
  EXPECT_TRUE(buildOutageWindows(cfg, 0.0, 5000.0).empty());
}

TEST(OutageSchedule, ExplicitWindowsMergedClippedAndDropped) {
  OutageScheduleConfig cfg;
  cfg.explicit_windows = {{150, 170}, {90, 120},  {110, 130}, {130, 140},
                          {-50, 10},  {290, 400}, {500, 600}};
  const auto w = buildOutageWindows(cfg, 0.0, 300.0);
  ASSERT_EQ(w.size(), 4u);
  EXPECT_DOUBLE_EQ(w[0].start_s, 0.0);  // clipped at the data start
  EXPECT_DOUBLE_EQ(w[0].end_s, 10.0);
  EXPECT_DOUBLE_EQ(w[1].start_s, 90.0);  // 90-120, 110-130 and touching 130-140 merged
  EXPECT_DOUBLE_EQ(w[1].end_s, 140.0);
  EXPECT_DOUBLE_EQ(w[2].start_s, 150.0);
  EXPECT_DOUBLE_EQ(w[3].start_s, 290.0);  // clipped at the data end
  EXPECT_DOUBLE_EQ(w[3].end_s, 300.0);    // and 500-600 dropped entirely
}

TEST(OutageSchedule, InvalidConfigsThrow) {
  OutageScheduleConfig cfg;
  cfg.period_s = 30.0;  // shorter than the length: windows would overlap
  EXPECT_THROW(buildOutageWindows(cfg, 0, 1000), std::invalid_argument);
  cfg = OutageScheduleConfig{};
  cfg.length_s = 0.0;
  EXPECT_THROW(buildOutageWindows(cfg, 0, 1000), std::invalid_argument);
  cfg = OutageScheduleConfig{};
  cfg.start_s = -5.0;
  EXPECT_THROW(buildOutageWindows(cfg, 0, 1000), std::invalid_argument);
  cfg = OutageScheduleConfig{};
  cfg.explicit_windows = {{10, 5}};
  EXPECT_THROW(buildOutageWindows(cfg, 0, 1000), std::invalid_argument);
}

TEST(OutageSchedule, WithholdRemovesFixesInsideIncludingBoundaries) {
  GnssSeries g;
  for (int t = 0; t <= 10; ++t) {
    GnssFix f;
    f.t_s = t;
    g.push_back(f);
  }
  const auto kept = withholdGnss(g, {{2.0, 4.0}, {7.0, 7.5}});
  std::vector<double> t;
  for (const auto& f : kept) t.push_back(f.t_s);
  EXPECT_EQ(t, (std::vector<double>{0, 1, 5, 6, 8, 9, 10}));
}

}  // namespace
}  // namespace graftnav
