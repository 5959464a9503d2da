// field/odometer.txt: the round trip, every input error named by file and line, the coverage
// warning with the uncovered spans, the streamed reader equal to the whole-file one, and the
// interpolation the estimators use.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "graftnav/io/odometer_io.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = test::makeTempDir("odometer") + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string errorOf(const std::string& text, const OdometerReadOptions& o = {}) {
  const std::string path = writeFile("odometer.txt", text);
  try {
    readOdometer(path, o);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(OdometerIo, WriteReadRoundTripAndStreamEqualsWhole) {
  OdometerSeries s;
  for (int k = 0; k < 5000; ++k) s.push_back({100.0 + 0.01 * k, 5.0 + 0.001 * k});
  const std::string path = test::makeTempDir("odometer_rt") + "/odometer.txt";
  writeOdometer(path, s);
  const OdometerSeries back = readOdometer(path);
  ASSERT_EQ(back.size(), s.size());
  for (size_t k = 0; k < s.size(); ++k) {
    EXPECT_NEAR(back[k].t_s, s[k].t_s, 1e-6);
    EXPECT_NEAR(back[k].speed_m_s, s[k].speed_m_s, 1e-6);
  }
  OdometerStreamReader stream(path, {}, 256);  // chunks far shorter than the file
  OdometerSample x;
  size_t n = 0;
  while (stream.next(&x)) {
    ASSERT_LT(n, back.size());
    EXPECT_EQ(x.t_s, back[n].t_s);
    EXPECT_EQ(x.speed_m_s, back[n].speed_m_s);
    ++n;
  }
  EXPECT_EQ(n, back.size());
  EXPECT_EQ(stream.report().records_kept, 5000);
}

TEST(OdometerIo, BadDataNamesFileAndLine) {
  EXPECT_THAT(errorOf("1.0 2.0\n1.1 -0.5\n"),
              HasSubstr("odometer.txt:2: speed -0.5 m/s is negative"));
  OdometerReadOptions reverse;
  reverse.forward_only = false;
  EXPECT_EQ(errorOf("1.0 2.0\n1.1 -0.5\n", reverse), "no error");
  EXPECT_THAT(errorOf("1.0 2.0\n1.1 nan\n"), HasSubstr("odometer.txt:2:"));
  EXPECT_THAT(errorOf("1.0 2.0\n1.1 nan\n"), HasSubstr("speed"));
  EXPECT_THAT(errorOf("1.0 2.0\ninf 2.0\n"), HasSubstr("odometer.txt:2:"));
  EXPECT_THAT(errorOf("1.0 2.0\n0.9 2.0\n"), HasSubstr("odometer.txt:2:"));
  EXPECT_THAT(errorOf("1.0 2.0\n0.9 2.0\n"), HasSubstr("not after"));
  EXPECT_THAT(errorOf("1.0 2.0\n1.0 2.1\n"), HasSubstr("odometer.txt:2:"));
  EXPECT_THAT(errorOf("1.0 2.0\n1.1 2.0 3.0\n"), HasSubstr("odometer.txt:2:"));
  EXPECT_THAT(errorOf("1.0 2.0\n1.1 250\n"), HasSubstr("odometer.txt:2: speed 250 m/s is beyond"));
  EXPECT_THAT(errorOf("1.0 abc\n"), HasSubstr("odometer.txt:1:"));
  EXPECT_THAT(errorOf("# only a comment\n"), HasSubstr("no odometer samples"));
}

TEST(OdometerIo, CoverageWarningListsTheUncoveredSpans) {
  OdometerSeries s;
  for (double t = 10.0; t <= 20.0 + 1e-9; t += 0.1) s.push_back({t, 3.0});
  for (double t = 25.0; t <= 40.0 + 1e-9; t += 0.1) s.push_back({t, 3.0});
  auto src = seriesOdometerSource(s);
  const std::vector<TimeWindow> spans = odometerUncoveredSpans(*src, 5.0, 45.0, 0.5);
  ASSERT_EQ(spans.size(), 3u);
  EXPECT_NEAR(spans[0].start_s, 5.0, 1e-9);
  EXPECT_NEAR(spans[0].end_s, 10.0, 1e-9);
  EXPECT_NEAR(spans[1].start_s, 20.0, 1e-6);
  EXPECT_NEAR(spans[1].end_s, 25.0, 1e-6);
  EXPECT_NEAR(spans[2].start_s, 40.0, 1e-6);
  EXPECT_NEAR(spans[2].end_s, 45.0, 1e-9);
  const std::string w = odometerCoverageWarning("CASE/field/odometer.txt", spans, 5.0, 45.0);
  EXPECT_THAT(w, HasSubstr("CASE/field/odometer.txt does not cover the IMU span"));
  EXPECT_THAT(w, HasSubstr("20.000 .. 25.000"));
  auto full = seriesOdometerSource(s);
  EXPECT_TRUE(odometerUncoveredSpans(*full, 10.0, 20.0, 0.5).empty());
  EXPECT_TRUE(odometerCoverageWarning("x", {}, 0.0, 1.0).empty());
}

TEST(OdometerInterpolator, InterpolatesInsideAndGivesNoneAcrossGapsAndOutside) {
  const OdometerSeries s = {{1.0, 2.0}, {1.1, 3.0}, {1.2, 3.0}, {5.0, 8.0}, {5.1, 9.0}};
  OdometerInterpolator it(seriesOdometerSource(s), 0.5);
  double v = 0.0;
  EXPECT_FALSE(it.at(0.9, &v));  // before the first sample
  ASSERT_TRUE(it.at(1.05, &v));
  EXPECT_NEAR(v, 2.5, 1e-12);
  ASSERT_TRUE(it.at(1.1, &v));
  EXPECT_NEAR(v, 3.0, 1e-12);
  EXPECT_FALSE(it.at(3.0, &v));  // inside the 3.8 s gap
  ASSERT_TRUE(it.at(5.05, &v));
  EXPECT_NEAR(v, 8.5, 1e-12);
  EXPECT_FALSE(it.at(5.2, &v));  // after the last
  const OdometerSeries bad = {{1.0, 2.0}, {0.5, 2.0}};
  OdometerInterpolator b(seriesOdometerSource(bad), 0.5);
  EXPECT_THROW(b.at(2.0, &v), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
