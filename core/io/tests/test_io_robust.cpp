// Robust reading of real files: slices of the real recordings read strictly, and
// the same slices with injected faults read under ImuReadPolicy/GnssReadPolicy/NavReadPolicy::real(),
// where every condition must be counted with its line number and nothing dropped silently.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/text_table.h"
#include "test_support.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

std::string realDir() { return test::sharedDir() + "/data/real/yandld_20220405_rtk/field/"; }

// First n lines of a file; empty when the file is absent.
std::vector<std::string> headLines(const std::string& path, int n) {
  std::vector<std::string> lines;
  std::ifstream f(path);
  std::string line;
  while (static_cast<int>(lines.size()) < n && std::getline(f, line)) lines.push_back(line);
  return lines;
}

void writeLines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream f(path, std::ios::binary);
  for (const auto& l : lines) f << l << '\n';
}

// Replaces column col (0-based) of a whitespace-separated line.
std::string setColumn(const std::string& line, int col, const std::string& value) {
  std::istringstream in(line);
  std::vector<std::string> tok;
  std::string t;
  while (in >> t) tok.push_back(t);
  tok.at(col) = value;
  std::string out;
  for (std::size_t i = 0; i < tok.size(); ++i) out += (i ? " " : "") + tok[i];
  return out;
}

#define REQUIRE_REAL_FILE(path) GRAFTNAV_REQUIRE_SHARED_PATH(path)

int exampleLine(const ReadReport& r, ReadCondition c, int index = 0) {
  int seen = 0;
  for (const auto& ex : r.examples)
    if (ex.condition == c && seen++ == index) return ex.line;
  return -1;
}

TEST(IoRobust, RealSlicesReadStrictly) {
  const std::string dir = test::makeTempDir("io");
  REQUIRE_REAL_FILE(realDir() + "tested_imu.txt");
  writeLines(dir + "/imu.txt", headLines(realDir() + "tested_imu.txt", 3000));
  writeLines(dir + "/gnss.pos", headLines(realDir() + "gnss.pos", 400));
  writeLines(dir + "/gnss_fixtype.txt", headLines(realDir() + "gnss_fixtype.txt", 400));
  writeLines(dir + "/reference.nav", headLines(realDir() + "reference.nav", 1000));
  ImuReadOptions opt;
  opt.nominal_rate_hz = 100.0;
  ReadReport imu_report;
  const ImuSeries imu = readImu(dir + "/imu.txt", opt, &imu_report);
  EXPECT_EQ(imu.size(), 3000u);
  EXPECT_TRUE(imu_report.clean()) << imu_report.summary();
  EXPECT_DOUBLE_EQ(imu.front().t_s, 203294.532);
  EXPECT_DOUBLE_EQ(imu.front().dt_s, 0.01);
  EXPECT_DOUBLE_EQ(imu.front().dvel_m_s.z(), -0.09122);

  std::vector<ReadReport> reports;
  const GnssSeries gnss =
      readGnss(dir + "/gnss.pos", dir + "/gnss_fixtype.txt", GnssReadPolicy::strict(), &reports);
  ASSERT_EQ(gnss.size(), 400u);
  int single = 0;
  for (const auto& f : gnss) {
    EXPECT_TRUE(f.fix_type == 1 || f.fix_type == 4 || f.fix_type == 5) << f.fix_type;
    EXPECT_GT(f.num_sv, 0);
    single += f.fix_type == 1;
  }
  EXPECT_GT(single, 0);
  EXPECT_EQ(gnss.front().fix_type, 1);
  EXPECT_EQ(gnss.front().num_sv, 45);
  // 10 Hz receive-time stamps: off whole seconds, counted but not an error.
  EXPECT_GT(reports[0].count(ReadCondition::kOffWholeSecond), 300);
  EXPECT_EQ(reports[0].count(ReadCondition::kZeroStd), 0);

  const NavSeries nav = readNav(dir + "/reference.nav");
  EXPECT_EQ(nav.size(), 1000u);
  EXPECT_EQ(nav.front().gnss_week, 2204);
}

TEST(IoRobust, ImuFaultsAreCountedWithLinesUnderRealPolicy) {
  const std::string dir = test::makeTempDir("io");
  REQUIRE_REAL_FILE(realDir() + "tested_imu.txt");
  std::vector<std::string> l = headLines(realDir() + "tested_imu.txt", 1000);
  // Faults, applied from the end so earlier indexes stay valid (line number = index + 1):
  //  uneven: stamp of line 701 moved by +0.003 s (intervals 1.3 and 0.7 x nominal)
  const double t700 = std::stod(l[700].substr(0, l[700].find(' ')));
  l[700] = setColumn(l[700], 0, std::to_string(t700 + 0.003));
  //  gap: original lines 501-505 deleted (one interval of 6 x nominal)
  l.erase(l.begin() + 500, l.begin() + 505);
  //  backwards: a copy of line 298 inserted after line 300 (new line 301)
  l.insert(l.begin() + 300, l[297]);
  //  duplicate: line 100 repeated identically (new line 101)
  l.insert(l.begin() + 100, l[99]);
  writeLines(dir + "/imu.txt", l);

  ImuReadOptions strict;
  strict.nominal_rate_hz = 100.0;
  EXPECT_THAT([&] { readImu(dir + "/imu.txt", strict); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("imu.txt:101: time")));

  // Line numbers after the edits: duplicate 101, backwards 302, gap 503 (original 506), uneven
  // 698 and 699 (original 701 and 702).
  ImuReadOptions real = strict;
  real.policy = ImuReadPolicy::real();
  ReadReport r;
  const ImuSeries imu = readImu(dir + "/imu.txt", real, &r);
  EXPECT_EQ(r.data_lines, 1000 - 5 + 2);
  EXPECT_EQ(r.count(ReadCondition::kDuplicateStamp), 1);
  EXPECT_EQ(exampleLine(r, ReadCondition::kDuplicateStamp), 101);
  EXPECT_EQ(r.count(ReadCondition::kBackwardsStamp), 1);
  EXPECT_EQ(exampleLine(r, ReadCondition::kBackwardsStamp), 302);
  EXPECT_EQ(r.count(ReadCondition::kGap), 1);
  EXPECT_EQ(exampleLine(r, ReadCondition::kGap), 503);
  EXPECT_EQ(r.count(ReadCondition::kUnevenInterval), 2);
  EXPECT_EQ(exampleLine(r, ReadCondition::kUnevenInterval, 0), 698);
  EXPECT_EQ(exampleLine(r, ReadCondition::kUnevenInterval, 1), 699);
  EXPECT_EQ(r.records_dropped, 2);
  EXPECT_EQ(r.records_kept, static_cast<int>(imu.size()));
  EXPECT_EQ(r.records_kept + r.records_dropped, r.data_lines);
  EXPECT_NEAR(imu[500].dt_s, 0.06, 1e-9);  // the sample after the gap carries the whole interval
  const std::string summary = r.summary();
  EXPECT_THAT(summary, HasSubstr("1 x gap"));
  EXPECT_THAT(summary, HasSubstr("line 503"));

  // The nominal rate is not needed: without it the median interval is used, same verdicts.
  ImuReadOptions no_rate = real;
  no_rate.nominal_rate_hz = 0.0;
  ReadReport r2;
  readImu(dir + "/imu.txt", no_rate, &r2);
  EXPECT_EQ(r2.counts, r.counts);

  // A duplicated stamp with different values is never repaired.
  std::vector<std::string> d = headLines(realDir() + "tested_imu.txt", 50);
  d.insert(d.begin() + 20, setColumn(d[19], 3, "1e-3"));
  writeLines(dir + "/dup_diff.txt", d);
  EXPECT_THAT([&] { readImu(dir + "/dup_diff.txt", real); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("dup_diff.txt:21: time")));
  // A long backwards run is not repairable.
  std::vector<std::string> b = headLines(realDir() + "tested_imu.txt", 400);
  const std::vector<std::string> early(b.begin(), b.begin() + 150);
  b.insert(b.begin() + 300, early.begin(), early.end());
  writeLines(dir + "/back_run.txt", b);
  EXPECT_THAT([&] { readImu(dir + "/back_run.txt", real); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("not repairable")));
}

// The block reader (and the chunked text reader under it) returns what readImu returns: the same
// samples, intervals, counted conditions and errors, whatever the block size.
TEST(IoRobust, ImuBlockReaderEqualsReadImu) {
  const std::string dir = test::makeTempDir("io_block");
  REQUIRE_REAL_FILE(realDir() + "tested_imu.txt");
  std::vector<std::string> l = headLines(realDir() + "tested_imu.txt", 3000);
  l.erase(l.begin() + 2500, l.begin() + 2503);   // a gap
  l.insert(l.begin() + 1200, l[1196]);           // a backwards stamp
  l.insert(l.begin() + 400, l[399]);             // a duplicate
  l.insert(l.begin() + 10, "# a comment line");  // skipped by both
  writeLines(dir + "/imu.txt", l);
  ImuReadOptions real;
  real.nominal_rate_hz = 100.0;
  real.policy = ImuReadPolicy::real();
  ReadReport expected_report;
  const ImuSeries expected = readImu(dir + "/imu.txt", real, &expected_report);
  ASSERT_GT(expected.size(), 2900u);
  EXPECT_EQ(readLastImuTime(dir + "/imu.txt"), expected.back().t_s);
  for (std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{4096}}) {
    ImuBlockReader reader(dir + "/imu.txt", real, block);
    ImuSeries got, samples;
    while (reader.next(&samples)) {
      EXPECT_LE(samples.size(), block);
      got.insert(got.end(), samples.begin(), samples.end());
    }
    ASSERT_EQ(got.size(), expected.size()) << "block " << block;
    for (std::size_t k = 0; k < got.size(); ++k) {
      ASSERT_EQ(got[k].t_s, expected[k].t_s) << k;
      ASSERT_EQ(got[k].dt_s, expected[k].dt_s) << k;
      ASSERT_EQ(got[k].dtheta_rad, expected[k].dtheta_rad) << k;
      ASSERT_EQ(got[k].dvel_m_s, expected[k].dvel_m_s) << k;
    }
    const ReadReport& r = reader.report();
    EXPECT_EQ(r.counts, expected_report.counts);
    EXPECT_EQ(r.data_lines, expected_report.data_lines);
    EXPECT_EQ(r.records_kept, expected_report.records_kept);
    EXPECT_EQ(r.records_dropped, expected_report.records_dropped);
    EXPECT_EQ(r.summary(), expected_report.summary());
  }
  // Strict: the same error, naming the file and line.
  ImuReadOptions strict;
  strict.nominal_rate_hz = 100.0;
  ImuBlockReader reader(dir + "/imu.txt", strict, 64);
  ImuSeries samples;
  EXPECT_THAT(
      [&] {
        while (reader.next(&samples)) {
        }
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("imu.txt:402: time")));
  EXPECT_THAT([&] { readImu(dir + "/imu.txt", strict); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("imu.txt:402: time")));
  // Without a nominal rate the block reader cannot check the first intervals: refused.
  EXPECT_THROW(ImuBlockReader(dir + "/imu.txt", ImuReadOptions{}), std::invalid_argument);
  // An empty file is an error, as for readImu.
  writeLines(dir + "/empty.txt", {});
  ImuBlockReader empty(dir + "/empty.txt", strict);
  EXPECT_THAT([&] { empty.next(&samples); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("no IMU samples")));
}

// The physical range check (ImuReadPolicy.max_*) holds in the block reader as in readImu, under
// both policies: the same error naming the file, line and column.
TEST(IoRobust, ImuBlockReaderAppliesThePhysicalRange) {
  const std::string dir = test::makeTempDir("io_block_range");
  std::vector<std::string> l;
  for (int k = 1; k <= 300; ++k)
    l.push_back(std::to_string(100.0 + 0.01 * k) + " 0.001 0 0 0 0 0.098");
  l[200] = std::to_string(100.0 + 0.01 * 201) + " 0.001 0 0 0 0 1e300";
  writeLines(dir + "/imu.txt", l);
  for (const bool lenient : {false, true}) {
    ImuReadOptions o;
    o.nominal_rate_hz = 100.0;
    if (lenient) o.policy = ImuReadPolicy::real();
    const auto error =
        ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("imu.txt:201: dvel_z"));
    EXPECT_THAT([&] { readImu(dir + "/imu.txt", o); }, error);
    for (std::size_t block : {std::size_t{1}, std::size_t{64}, std::size_t{4096}}) {
      ImuBlockReader reader(dir + "/imu.txt", o, block);
      ImuSeries samples;
      EXPECT_THAT(
          [&] {
            while (reader.next(&samples)) {
            }
          },
          error)
          << block;
    }
  }
}

// Chunks shorter than a line: every line still comes whole, with its number.
TEST(IoRobust, StreamingTextReaderEqualsWholeFileReader) {
  const std::string dir = test::makeTempDir("io_chunks");
  writeLines(dir + "/t.txt",
             {"1 2 3", "", "# comment", "4 5.5 -6e-3 7 8 9 10 11 12 13 14 15", "  \t", "16"});
  {
    std::ofstream f(dir + "/t.txt", std::ios::app | std::ios::binary);
    f << "17 18";  // no newline at the end
  }
  TextTableReader whole(dir + "/t.txt");
  TextTableReader chunked = TextTableReader::streaming(dir + "/t.txt", 1);
  int lines = 0;
  while (whole.next()) {
    ASSERT_TRUE(chunked.next());
    ++lines;
    EXPECT_EQ(chunked.lineNumber(), whole.lineNumber());
    EXPECT_EQ(chunked.lineText(), whole.lineText());
    ASSERT_EQ(chunked.columnCount(), whole.columnCount());
    for (int c = 0; c < whole.columnCount(); ++c) EXPECT_EQ(chunked.value(c), whole.value(c));
  }
  EXPECT_FALSE(chunked.next());
  EXPECT_EQ(lines, 4);
  EXPECT_THROW(chunked.physicalLineCount(), std::logic_error);
}

TEST(IoRobust, GnssFaultsAreCountedUnderRealPolicy) {
  const std::string dir = test::makeTempDir("io");
  REQUIRE_REAL_FILE(realDir() + "gnss.pos");
  std::vector<std::string> pos = headLines(realDir() + "gnss.pos", 200);
  std::vector<std::string> ft = headLines(realDir() + "gnss_fixtype.txt", 200);
  pos[9] = setColumn(pos[9], 5, "0.0000");  // zero std east at line 10
  pos.insert(pos.begin() + 20, pos[19]);    // identical duplicate at line 21
  ft.resize(190);                           // the last 10 .pos epochs have no fix type
  writeLines(dir + "/gnss.pos", pos);
  writeLines(dir + "/gnss_fixtype.txt", ft);

  EXPECT_THAT(
      [&] { readGnssPos(dir + "/gnss.pos"); },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("gnss.pos:10: std_east is '0.0000'")));
  std::vector<ReadReport> reports;
  const GnssReadPolicy real = GnssReadPolicy::real();
  const GnssSeries g = readGnss(dir + "/gnss.pos", dir + "/gnss_fixtype.txt", real, &reports);
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(g.size(), 200u);
  EXPECT_EQ(reports[0].count(ReadCondition::kZeroStd), 1);
  EXPECT_EQ(exampleLine(reports[0], ReadCondition::kZeroStd), 10);
  EXPECT_DOUBLE_EQ(g[9].std_ned_m.y(), real.std_floor_m);
  EXPECT_EQ(reports[0].count(ReadCondition::kDuplicateStamp), 1);
  EXPECT_EQ(exampleLine(reports[0], ReadCondition::kDuplicateStamp), 21);
  EXPECT_EQ(reports[0].records_dropped, 1);
  EXPECT_EQ(reports[1].count(ReadCondition::kUnmatchedEpoch), 10);
  double t189 = 0.0;
  int type189 = -1;
  std::istringstream(ft[189]) >> t189 >> type189;
  EXPECT_EQ(g[189].fix_type, type189);
  EXPECT_EQ(g[190].fix_type, 0);  // unknown
  // Strict: the unmatched epochs are an error naming the fix-type file.
  EXPECT_THAT(
      [&] {
        readGnss(dir + "/gnss.pos", dir + "/gnss_fixtype.txt", [] {
          GnssReadPolicy p;
          p.zero_std = ReadRule::kRepair;
          p.duplicate_stamp = ReadRule::kRepair;
          return p;
        }());
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("gnss_fixtype.txt: GNSS epoch")));
}

// GnssStreamReader (one epoch at a time) against readGnss on the faulty slice above: the same
// fixes, repairs, fix types and reports under the real policy, the same error under the strict.
TEST(IoRobust, GnssStreamReaderEqualsReadGnss) {
  const std::string dir = test::makeTempDir("io");
  REQUIRE_REAL_FILE(realDir() + "gnss.pos");
  std::vector<std::string> pos = headLines(realDir() + "gnss.pos", 200);
  std::vector<std::string> ft = headLines(realDir() + "gnss_fixtype.txt", 200);
  pos[9] = setColumn(pos[9], 5, "0.0000");
  pos.insert(pos.begin() + 20, pos[19]);
  ft.erase(ft.begin() + 50);  // a .pos epoch without fix type inside the file
  ft.resize(190);
  writeLines(dir + "/gnss.pos", pos);
  writeLines(dir + "/gnss_fixtype.txt", ft);
  const std::string p = dir + "/gnss.pos", t = dir + "/gnss_fixtype.txt";
  for (const std::string& fixtype : {t, std::string()}) {
    std::vector<ReadReport> want_reports;
    const GnssSeries want = readGnss(p, fixtype, GnssReadPolicy::real(), &want_reports);
    GnssStreamReader reader(p, fixtype, GnssReadPolicy::real(), 256);  // chunk boundaries
    GnssSeries got;
    for (GnssFix f; reader.next(&f);) got.push_back(f);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(got[i].t_s, want[i].t_s) << i;
      EXPECT_EQ(got[i].pos.lat_rad, want[i].pos.lat_rad) << i;
      EXPECT_EQ(got[i].pos.h_m, want[i].pos.h_m) << i;
      EXPECT_EQ(got[i].std_ned_m, want[i].std_ned_m) << i;
      EXPECT_EQ(got[i].fix_type, want[i].fix_type) << i;
      EXPECT_EQ(got[i].num_sv, want[i].num_sv) << i;
    }
    const std::vector<ReadReport> got_reports = reader.reports();
    ASSERT_EQ(got_reports.size(), want_reports.size());
    for (std::size_t r = 0; r < want_reports.size(); ++r) {
      EXPECT_EQ(got_reports[r].summary(), want_reports[r].summary()) << r;
      EXPECT_EQ(got_reports[r].records_kept, want_reports[r].records_kept) << r;
      EXPECT_EQ(got_reports[r].data_lines, want_reports[r].data_lines) << r;
    }
  }
  EXPECT_EQ(readGnss(p, t, GnssReadPolicy::real())[50].fix_type, 0);
  GnssReadPolicy strict_ft = GnssReadPolicy::real();
  strict_ft.unmatched_fix_type = ReadRule::kError;
  GnssStreamReader strict(p, t, strict_ft);
  EXPECT_THAT(
      [&] {
        for (GnssFix f; strict.next(&f);) {
        }
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("gnss_fixtype.txt: GNSS epoch")));
  GnssStreamReader zero_std(p, t);
  EXPECT_THAT(
      [&] {
        for (GnssFix f; zero_std.next(&f);) {
        }
      },
      ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("gnss.pos:10: std_east is '0.0000'")));
}

TEST(IoRobust, NavDuplicateRepairedUnderRealPolicy) {
  const std::string dir = test::makeTempDir("io");
  REQUIRE_REAL_FILE(realDir() + "reference.nav");
  std::vector<std::string> nav = headLines(realDir() + "reference.nav", 300);
  nav.insert(nav.begin() + 50, nav[49]);
  writeLines(dir + "/reference.nav", nav);
  EXPECT_THROW(readNav(dir + "/reference.nav"), std::runtime_error);
  ReadReport r;
  EXPECT_EQ(readNav(dir + "/reference.nav", NavReadPolicy::real(), &r).size(), 300u);
  EXPECT_EQ(r.count(ReadCondition::kDuplicateStamp), 1);
  EXPECT_EQ(exampleLine(r, ReadCondition::kDuplicateStamp), 51);
}

TEST(IoRobust, PolicyRulesAreValidated) {
  ImuReadPolicy p;
  p.gap = ReadRule::kRepair;  // nothing would be a faithful repair of missing samples
  EXPECT_THAT([&] { p.validate(); },
              ::testing::ThrowsMessage<std::invalid_argument>(HasSubstr("ImuReadPolicy.gap")));
  p = ImuReadPolicy::real();
  EXPECT_NO_THROW(p.validate());
  p.duplicate_stamp = ReadRule::kWarn;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  GnssReadPolicy g;
  g.zero_std = ReadRule::kWarn;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = GnssReadPolicy::real();
  g.std_floor_m = 0.0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  NavReadPolicy n;
  n.backwards_stamp = ReadRule::kWarn;
  EXPECT_THROW(n.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav
