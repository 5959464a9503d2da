// navigate with a static or in-motion alignment and a time range, streamed (the IMU, the GNSS and
// the reference read as files, nothing held but the alignment's samples) against the in-memory path (the same estimators without their
// streamed form): every number of every file equal, on ranges that start after the IMU's start
// and end before its end, with outages at the range's edges; a broken IMU line named with its
// file and line by both paths, inside the range or outside it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "graftnav/estimators/estimator_table.h"
#include "graftnav/navigate/navigate_run.h"
#include "graftnav/navigate/navigate_setup.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

// The estimator table without the streamed forms: every run of it holds its series.
EstimatorRegistry inMemoryTable() {
  EstimatorRegistry r;
  for (EstimatorEntry e : estimatorTable().entries()) {
    e.stream = {};
    r.add(e);
  }
  return r;
}

std::string fileText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The tokens of a text (split at white space, commas, brackets, colons and quotes).
std::vector<std::string> tokens(const std::string& text) {
  std::vector<std::string> out;
  std::string t;
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c)) || c == ',' || c == '[' || c == ']' ||
        c == '{' || c == '}' || c == ':' || c == '"') {
      if (!t.empty()) out.push_back(t);
      t.clear();
    } else {
      t += c;
    }
  }
  if (!t.empty()) out.push_back(t);
  return out;
}

// Every token of the two files equal: numbers as doubles (NaN equal to NaN), words as text. Names
// the first differing token; returns how many differ.
int differingNumbers(const fs::path& a, const fs::path& b) {
  const std::vector<std::string> ta = tokens(fileText(a)), tb = tokens(fileText(b));
  EXPECT_EQ(ta.size(), tb.size()) << a.filename();
  int differ = 0;
  for (std::size_t k = 0; k < std::min(ta.size(), tb.size()); ++k) {
    char* end_a = nullptr;
    char* end_b = nullptr;
    const double va = std::strtod(ta[k].c_str(), &end_a), vb = std::strtod(tb[k].c_str(), &end_b);
    const bool numbers = *end_a == '\0' && *end_b == '\0';
    const bool same = numbers ? (va == vb || (std::isnan(va) && std::isnan(vb))) : ta[k] == tb[k];
    if (!same && differ++ == 0)
      ADD_FAILURE() << a.filename() << " token " << k << ": " << ta[k] << " against " << tb[k];
  }
  return differ;
}

struct RangeCase {
  std::string name;
  std::string alignment;  // given | static
  double start_s, end_s;  // the time range (s of week)
  bool windows;           // outages at the range's edges instead of the schedule
  bool gnss_section;      // a gnss: section (the GNSS held and selected)
};

std::string runConfig(const RangeCase& c, const std::string& dir) {
  const std::string path = dir + "/" + c.name + ".yaml";
  std::ofstream f(path);
  f << std::setprecision(12) << "ekf:\n  alignment: " << c.alignment
    << "\n  static_alignment_s: 25\n";
  f << "time_range:\n  start_s: " << c.start_s << "\n  end_s: " << c.end_s << "\n";
  if (c.windows) {  // one outage from the range's start, one to its end
    f << "outages:\n  windows: [[" << c.start_s << ", " << c.start_s + 60 << "], [" << c.end_s - 50
      << ", " << c.end_s << "]]\n";
  } else {
    f << "outages:\n  length_s: 30\n  period_s: 120\n  start_s: 40\n";
  }
  if (c.gnss_section) f << "gnss:\n  min_spacing_s: 0.5\n";
  return path;
}

NavigateRequest request(const RangeCase& c, const std::string& case_dir, const std::string& out,
                        const std::string& estimator, const std::string& dir) {
  fs::create_directories(out);
  NavigateRequest q;
  q.case_dir = case_dir;
  q.out_dir = out;
  q.imu = "tested";
  q.estimator = estimator;
  q.run_config = runConfig(c, dir);
  return q;
}

class StreamedNavigateRange : public ::testing::TestWithParam<RangeCase> {};

TEST_P(StreamedNavigateRange, EveryNumberEqualsTheInMemoryRun) {
  const RangeCase& c = GetParam();
  const std::string dir = test::makeTempDir("streamed_range_" + c.name);
  const std::string case_dir = test::sourceDir() + "/data/sample_mems";
  const EstimatorRegistry memory_table = inMemoryTable();
  for (const std::string estimator : {"ekf", "fgo-window"}) {
    const NavigateRequest qs = request(c, case_dir, dir + "/s_" + estimator, estimator, dir);
    const NavigateRequest qm = request(c, case_dir, dir + "/m_" + estimator, estimator, dir);
    const NavigateSetup ss = prepareNavigate(qs, estimatorTable(), RunMessages{});
    const NavigateSetup sm = prepareNavigate(qm, memory_table, RunMessages{});
    ASSERT_TRUE(ss.stream);
    EXPECT_EQ(ss.stream_gnss, !c.gnss_section && c.alignment != "motion");
    EXPECT_TRUE(ss.pr.imu.empty() && ss.imu.imu.empty() && ss.c.reference.empty());
    ASSERT_FALSE(sm.stream);
    ASSERT_GE(sm.pr.imu.front().t_s - sm.pr.imu.front().dt_s, c.start_s - 1e-6);  // cut
    ASSERT_LT(sm.pr.imu.front().t_s - sm.pr.imu.front().dt_s, c.start_s + 0.02);
    ASSERT_LE(sm.pr.imu.back().t_s, c.end_s);
    ASSERT_GT(sm.pr.imu.back().t_s, c.end_s - 0.02);
    EXPECT_EQ(ss.pr.outages.size(), sm.pr.outages.size());
    EXPECT_EQ(ss.notes, sm.notes);
    const NavigateOutcome os = runNavigate(ss, qs.out_dir, estimatorTable(), RunMessages{});
    const NavigateOutcome om = runNavigate(sm, qm.out_dir, memory_table, RunMessages{});
    EXPECT_GT(os.files.epochs, 1000u);
    EXPECT_EQ(os.files.epochs, om.files.epochs);
    for (const char* f : {"solution.nav", "state_std.txt", "errors.json", "errors.csv",
                          "outage_drift.csv", "imu_errors.txt"}) {
      const fs::path a = fs::path(qs.out_dir) / f, b = fs::path(qm.out_dir) / f;
      ASSERT_EQ(fs::exists(a), fs::exists(b)) << estimator << " " << f;
      if (!fs::exists(a)) continue;
      EXPECT_FALSE(fileText(a).empty()) << f;
      EXPECT_EQ(differingNumbers(a, b), 0) << estimator << " " << f;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    SampleMems, StreamedNavigateRange,
    ::testing::Values(
        // At rest from 456430.4 to 456468.7: levelled over 25 s; an outage from the range's start
        // (during the alignment) and one to its end, 60 s before the IMU's.
        RangeCase{"static_edges", "static", 456430.0, 457150.0, true, false},
        // A start between two samples (50 Hz), an end before the last one, the GNSS held.
        RangeCase{"static_gnss_held", "static", 456430.013, 457149.99, true, true},
        RangeCase{"given_schedule", "given", 456500.0, 457100.0, false, false},
        // In motion from 456474 s (3 m/s, 44 s into the range): the prefix is read again longer
        // until the epoch's levelling window lies inside it.
        RangeCase{"motion_edges", "motion", 456430.0, 457150.0, true, false},
        RangeCase{"motion_gnss_held", "motion", 456340.02, 457000.0, false, true}),
    [](const ::testing::TestParamInfo<RangeCase>& p) { return p.param.name; });

// The sample with its tested IMU's line `line` broken (a field that is not a number).
std::string caseWithBrokenImuLine(const std::string& tag, int line) {
  const std::string dir = test::makeTempDir(tag);
  const fs::path from = fs::path(test::sourceDir()) / "data/sample_mems";
  fs::copy(from, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const fs::path imu = fs::path(dir) / "field/tested_imu.txt";
  std::istringstream in(fileText(imu));
  std::ofstream out(imu, std::ios::trunc);
  std::string text;
  for (int k = 1; std::getline(in, text); ++k)
    out << (k == line ? "456340.5 x 1 2 3 4 5" : text) << "\n";
  return dir;
}

TEST(StreamedNavigateRange, ABrokenImuLineIsNamedInsideAndOutsideTheRange) {
  // The range [456430, 457150] keeps lines 4501..40500 of the 50-Hz file.
  for (int line : {3, 20000, 43000}) {
    const std::string case_dir = caseWithBrokenImuLine("streamed_range_broken", line);
    const RangeCase c{"broken", "static", 456430.0, 457150.0, false, false};
    const std::string where = "tested_imu.txt:" + std::to_string(line);
    std::string streamed_error, memory_error;
    const std::string dir = case_dir + "/runs";
    streamed_error = test::errorOf([&] {
      prepareNavigate(request(c, case_dir, dir + "/s", "ekf", dir), estimatorTable(), {});
    });
    memory_error = test::errorOf([&] {
      prepareNavigate(request(c, case_dir, dir + "/m", "ekf", dir), inMemoryTable(), {});
    });
    EXPECT_NE(streamed_error.find(where), std::string::npos) << streamed_error;
    EXPECT_EQ(streamed_error, memory_error);
  }
}

}  // namespace
}  // namespace graftnav
