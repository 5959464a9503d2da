// Fault injection: corrupted inputs, bad option values, a full disk, a failing write and a run
// killed with SIGKILL. Every test asserts one of two outcomes:
//   (a) a failing exit code, a message naming the file (and line) or the option, and no result
//       file in --out;
//   (b) exit code 0, finite numbers in every result, and a warning naming the problem.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/inotify.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Core>
#include <fcntl.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "graftnav/calibration/calibration_io.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/mismatch/locate.h"
#include "test_support.h"

extern char** environ;

namespace graftnav {
namespace {
namespace fs = std::filesystem;

std::string sample(const std::string& grade) { return test::sourceDir() + "/data/sample_" + grade; }
std::string sampleConfig() { return test::sourceDir() + "/configs/evaluate_sample.yaml"; }

std::string copyCase(const std::string& grade, const std::string& tag) {
  const std::string dst =
      test::makeTempDir(tag + "_case") + "/case";  // makeTempDir(tag) wipes its folder
  fs::copy(sample(grade), dst, fs::copy_options::recursive);
  return dst;
}

std::vector<std::string> readLines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(f, l);) lines.push_back(l);
  return lines;
}

void writeLines(const std::string& path, const std::vector<std::string>& lines) {
  std::ofstream f(path);  // test input, not a result
  for (const auto& l : lines) f << l << "\n";
}

// Replaces whitespace-separated column `col` (0 = time) of data line `line` (1-based) by `value`.
void setColumn(const std::string& path, int line, int col, const std::string& value) {
  std::vector<std::string> lines = readLines(path);
  std::istringstream in(lines.at(line - 1));
  std::vector<std::string> cols;
  for (std::string c; in >> c;) cols.push_back(c);
  cols.at(col) = value;
  std::string joined;
  for (const auto& c : cols) joined += (joined.empty() ? "" : " ") + c;
  lines[line - 1] = joined;
  writeLines(path, lines);
}

// Every regular file in dir (recursively), hidden temporaries included; empty when dir is absent.
std::vector<std::string> filesIn(const std::string& dir) {
  std::vector<std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(e.path().filename().string());
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + " ";
  return s;
}

// Outcome (a): failed, said why (every token appears in the output), left no file in `out`.
void expectFailedCleanly(const test::CommandOutput& r, const std::string& out,
                         const std::vector<std::string>& tokens) {
  EXPECT_NE(r.exit_code, 0) << r.text;
  for (const auto& t : tokens)
    EXPECT_NE(r.text.find(t), std::string::npos) << "missing '" << t << "' in:\n" << r.text;
  EXPECT_TRUE(filesIn(out).empty()) << "left in " << out << ": " << join(filesIn(out));
}

// Every number in a JSON document is finite (nlohmann writes NaN as null; nulls are counted apart).
int countNonFinite(const nlohmann::json& j) {
  if (j.is_number_float()) return std::isfinite(j.get<double>()) ? 0 : 1;
  int n = 0;
  if (j.is_structured())
    for (const auto& v : j) n += countNonFinite(v);
  return n;
}

// No "nan" or "inf" token in a text result.
bool hasNonFiniteToken(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  static const std::regex re(R"((^|[,\s|])[-+]?(nan|inf)([,\s|]|$))", std::regex::icase);
  return std::regex_search(ss.str(), re);
}

// A small tmpfs mounted on `dir` for the test's lifetime (root only; mounted() false otherwise), so
// that a failing assertion does not leave it mounted.
class TmpfsMount {
 public:
  TmpfsMount(const std::string& dir, const char* size) : dir_(dir) {
    ok_ = geteuid() == 0 && mount("tmpfs", dir.c_str(), "tmpfs", 0, size) == 0;
  }
  ~TmpfsMount() {
    if (ok_) umount(dir_.c_str());
  }
  bool mounted() const { return ok_; }

 private:
  std::string dir_;
  bool ok_ = false;
};

// --- option values ------------------------------------------------------------------------------

TEST(Faults, NegativeOrZeroOutageOptionsAreErrorsNamingTheFlag) {
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--outage-length", "-5"}, {"--outage-period", "0"}, {"--outage-start", "-1"}}) {
    const std::string out = test::makeTempDir("opt") + "/out";
    const test::CommandOutput r = test::runGraftnav("navigate " + sample("tactical") + " --out " +
                                                    out + " --no-plots " + flag + " " + value);
    expectFailedCleanly(r, out, {flag, value});
  }
  const std::string out = test::makeTempDir("opt_compare") + "/out";
  const test::CommandOutput r = test::runGraftnav(
      "compare " + sample("tactical") + " --estimators ekf --out " + out + " --outage-length -5");
  expectFailedCleanly(r, out, {"--outage-length", "-5"});
}

TEST(Faults, UnknownEstimatorFailsBeforeEvaluateWritesAnything) {
  const std::string out = test::makeTempDir("est") + "/out";
  const test::CommandOutput r =
      test::runGraftnav("evaluate " + sample("tactical") + " --out " + out + " --config " +
                        sampleConfig() + " --estimator kalmanish --no-plots");
  expectFailedCleanly(r, out, {"--estimator", "kalmanish"});
}

TEST(Faults, OutageStartBeyondTheDataIsAnError) {
  const std::string out = test::makeTempDir("beyond") + "/out";
  test::CommandOutput r =
      test::runGraftnav("evaluate " + sample("tactical") + " --out " + out + " --config " +
                        sampleConfig() + " --outage-start 1000 --no-plots");
  expectFailedCleanly(r, out, {"outage start 1000", "--outage-start"});
  r = test::runGraftnav("navigate " + sample("tactical") + " --out " + out +
                        " --outage-start 1000 --no-plots");
  expectFailedCleanly(r, out, {"outage start 1000", "--outage-start"});
}

// --- reference and GNSS coverage ----------------------------------------------------------------

TEST(Faults, TruthMissingInsideAnOutageIsAnError) {
  const std::string c = copyCase("tactical", "truth_part");
  const std::string truth = c + "/field/truth.nav";
  std::vector<std::string> lines = readLines(truth);
  lines.resize(lines.size() / 3);  // 290 s of 870: the outages from 360 s on have no truth
  writeLines(truth, lines);
  const std::string out = test::makeTempDir("truth_part") + "/out";
  const test::CommandOutput r = test::runGraftnav("evaluate " + c + " --out " + out + " --config " +
                                                  sampleConfig() + " --no-plots");
  expectFailedCleanly(r, out, {"truth.nav", "no reference epoch inside the outage"});
}

TEST(Faults, TruthCoveringPartOfTheSpanWarnsAndStaysFinite) {
  const std::string c = copyCase("tactical", "truth_part2");
  const std::string truth = c + "/field/truth.nav";
  std::vector<std::string> lines = readLines(truth);
  lines.resize(lines.size() * 7 /
               8);  // 761 s of 870 s; the outages (100, 300, 500, 700 s + 30 s) keep their truth
  writeLines(truth, lines);
  const std::string out = test::makeTempDir("truth_part2") + "/out";
  const test::CommandOutput r =
      test::runGraftnav("navigate " + c + " --out " + out +
                        " --outage-start 100 --outage-length 30 --outage-period 200 --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("warning: " + truth + " covers"), std::string::npos) << r.text;
  std::ifstream f(out + "/errors.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_EQ(countNonFinite(j), 0);
  EXPECT_TRUE(j["outage"]["horizontal_m"].is_number());
  EXPECT_EQ(j["outages"]["count"], 4);
  EXPECT_FALSE(hasNonFiniteToken(out + "/errors.csv"));
}

TEST(Faults, NoGnssEpochInsideTheImuSpanIsAnErrorUnlessFreeInertial) {
  const std::string c = copyCase("tactical", "gnss_out");
  const std::string pos = c + "/field/gnss.pos";
  std::vector<std::string> lines = readLines(pos);
  for (std::size_t i = 0; i < lines.size(); ++i)
    setColumn(pos, static_cast<int>(i + 1), 0, std::to_string(460000.0 + static_cast<double>(i)));
  const std::string out = test::makeTempDir("gnss_out") + "/out";
  test::CommandOutput r = test::runGraftnav("navigate " + c + " --out " + out + " --no-plots");
  expectFailedCleanly(r, out, {pos, "0 of 871 GNSS epochs", "--free-inertial"});
  r = test::runGraftnav("navigate " + c + " --out " + out + " --free-inertial --no-plots");
  EXPECT_EQ(r.exit_code, 0) << r.text;
}

TEST(Faults, AOneLineGnssFileIsAnError) {
  const std::string c = copyCase("tactical", "gnss_one");
  const std::string pos = c + "/field/gnss.pos";
  std::vector<std::string> lines = readLines(pos);
  lines.resize(1);
  writeLines(pos, lines);
  const std::string out = test::makeTempDir("gnss_one") + "/out";
  test::CommandOutput r = test::runGraftnav("navigate " + c + " --out " + out + " --no-plots");
  expectFailedCleanly(r, out, {pos, "1 of 1 GNSS epochs"});
  r = test::runGraftnav("evaluate " + c + " --out " + out + " --config " + sampleConfig() +
                        " --no-plots");
  expectFailedCleanly(r, out, {pos, "1 of 1 GNSS epochs"});
}

// --- IMU values ---------------------------------------------------------------------------------

TEST(Faults, ImuValueOutOfPhysicalRangeNamesFileAndLine) {
  const std::string c = copyCase("tactical", "imu_range");
  setColumn(c + "/field/ref_imu.txt", 1234, 2, "1e300");
  const std::string out = test::makeTempDir("imu_range") + "/out";
  test::CommandOutput r = test::runGraftnav("navigate " + c + " --out " + out + " --no-plots");
  expectFailedCleanly(r, out, {c + "/field/ref_imu.txt:1234", "dtheta_y", "deg/s"});
  // Through grafting (the reference IMU) and in the tested IMU: the same error, nothing written.
  r = test::runGraftnav("evaluate " + c + " --out " + out + " --config " + sampleConfig() +
                        " --no-plots");
  expectFailedCleanly(r, out, {"ref_imu.txt:1234"});
  const std::string c2 = copyCase("tactical", "imu_range2");
  setColumn(c2 + "/field/tested_imu.txt", 78, 6, "1e300");
  r = test::runGraftnav("evaluate " + c2 + " --out " + out + " --config " + sampleConfig() +
                        " --no-plots");
  expectFailedCleanly(r, out, {"tested_imu.txt:78", "dvel_z", " g,"});
  // diagnose reads with the lenient policies: the physical range still holds (a 1e300 reaching the
  // locator makes its noise limit NaN).
  const std::string c3 = copyCase("mems", "imu_range3");
  setColumn(c3 + "/field/tested_imu.txt", 321, 1, "1e300");
  r = test::runGraftnav("diagnose " + c3 + " --out " + out + " --no-plots");
  expectFailedCleanly(r, out, {"tested_imu.txt:321", "dtheta_x"});
}

TEST(Faults, ImuRangeLimitsAreTheStatedOnes) {
  // 200 Hz: 1e4 deg/s is 0.8727 rad per sample, 100 g is 4.903 m/s per sample.
  const std::string dir = test::makeTempDir("imu_limits");
  auto file = [&](double dtheta, double dvel) {
    std::vector<std::string> lines;
    for (int k = 1; k <= 10; ++k)
      lines.push_back(std::to_string(1000.0 + 0.005 * k) + " " + std::to_string(dtheta) +
                      " 0 0 0 0 " + std::to_string(dvel));
    writeLines(dir + "/imu.txt", lines);
    return dir + "/imu.txt";
  };
  ImuReadOptions o;
  o.nominal_rate_hz = 200.0;
  EXPECT_NO_THROW(readImu(file(0.87, 4.9), o));
  EXPECT_THROW(readImu(file(0.88, 0.0), o), std::runtime_error);
  EXPECT_THROW(readImu(file(0.0, -4.91), o), std::runtime_error);
  o.policy = ImuReadPolicy::real();  // the lenient policy does not relax the physical range
  EXPECT_THROW(readImu(file(0.88, 0.0), o), std::runtime_error);
}

TEST(Faults, NanResidualInTheLocatorIsAnErrorNotALoop) {
  GridSpec grid;
  grid.bin_s = 0.05;
  grid.count = 2000;
  Eigen::MatrixXd residual = Eigen::MatrixXd::Constant(grid.count, 6, 1e-3);
  for (int i = 0; i < grid.count; ++i) residual(i, 0) = 1e-3 * std::sin(0.1 * i);
  residual(500, 2) = std::nan("");
  const std::vector<std::string> regimes(grid.count, "cruising");
  try {
    locateResidual(residual, grid, regimes);
    FAIL() << "a NaN residual was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

// --- lab static record --------------------------------------------------------------------------

TEST(Faults, ShortLabStaticRecordIsAnErrorBelowTheFloor) {
  const std::string c = copyCase("tactical", "static_short");
  const std::string st = c + "/lab/static.txt";
  std::vector<std::string> lines = readLines(st);
  lines.resize(20);  // 0.4 s at 50 Hz
  writeLines(st, lines);
  const std::string out = test::makeTempDir("static_short") + "/out";
  const test::CommandOutput r = test::runGraftnav("evaluate " + c + " --out " + out + " --config " +
                                                  sampleConfig() + " --no-plots");
  expectFailedCleanly(r, out, {st, "0.40 s", "60 s floor"});
}

TEST(Faults, LabStaticRecordShorterThanTheOutageSpacingWarnsAndStaysFinite) {
  // The sample's 120 s record against outages every 150 s: a warning, finite results.
  const std::string out = test::makeTempDir("static_warn") + "/out";
  const test::CommandOutput r =
      test::runGraftnav("evaluate " + sample("tactical") + " --out " + out + " --config " +
                        sampleConfig() + " --outage-start 30 --outage-period 150 --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(
      r.text.find(
          "static.txt: the lab static record lasts 120.0 s, shorter than the outage spacing of "
          "150.0 s"),
      std::string::npos)
      << r.text;
  std::ifstream f(out + "/evaluation.json");
  EXPECT_EQ(countNonFinite(nlohmann::json::parse(f)), 0);
  for (const std::string name : {"evaluation.csv", "outage_drift.csv", "tables.md"})
    EXPECT_FALSE(hasNonFiniteToken(out + "/" + name)) << name;
}

// --- statistics that cannot be computed, lenient reading ----------------------------------------

TEST(Faults, AbsentOutageStatisticsAreNullWithAWarning) {
  const std::string out = test::makeTempDir("absent") + "/out";
  const test::CommandOutput r =
      test::runGraftnav("navigate " + sample("tactical") + " --out " + out + " --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(
      r.text.find("errors.json: absent (null): /outage/*, /outage_max/* (no outage statistics"),
      std::string::npos)
      << r.text;
  std::ifstream f(out + "/errors.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_EQ(countNonFinite(j), 0);
  EXPECT_TRUE(j["outage"]["horizontal_m"].is_null());
  EXPECT_TRUE(j["overall"]["horizontal_rms_m"].is_number());
  EXPECT_FALSE(hasNonFiniteToken(out + "/errors.csv"));
}

TEST(Faults, LenientNavigatePrintsTheReadersRepairReport) {
  const std::string c = copyCase("tactical", "lenient");
  const std::string imu = c + "/field/ref_imu.txt";
  std::vector<std::string> lines = readLines(imu);
  lines.insert(lines.begin() + 500, lines[499]);  // an identical duplicate: repairable
  writeLines(imu, lines);
  const std::string out = test::makeTempDir("lenient") + "/out";
  test::CommandOutput r = test::runGraftnav("navigate " + c + " --out " + out + " --no-plots");
  expectFailedCleanly(r, out, {imu + ":501"});
  r = test::runGraftnav("navigate " + c + " --out " + out + " --no-plots --lenient");
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("warning: " + imu), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("501"), std::string::npos) << r.text;
}

// --- writers ------------------------------------------------------------------------------------

// Each command's writers under a file-size limit of 0: every write fails with EFBIG. The command
// must fail with errno's text, naming where it wrote, and leave nothing, not even a temporary
// file. (SIGXFSZ is ignored so the write returns the error instead of killing the process.)
// diagnose spools the tested record to TMPDIR before it writes a result, so that write fails
// first.
TEST(Faults, EveryCommandsWritersFailCleanlyWhenAWriteFails) {
  const std::string limit = "trap '' XFSZ; ulimit -f 0;";
  const std::string tmp = test::makeTempDir("writers");
  struct Cmd {
    std::string args;
    std::string out;
    std::string where = {};  // named in the error when not `out`
  };
  const std::vector<Cmd> cmds = {
      {"navigate " + sample("tactical") + " --no-plots --out ", tmp + "/navigate"},
      {"calibrate " + sample("tactical") + " --no-plots --out ", tmp + "/calibrate"},
      {"compare " + sample("tactical") + " --imu tested --estimators ekf --out ", tmp + "/compare"},
      {"evaluate " + sample("tactical") + " --config " + sampleConfig() + " --no-plots --out ",
       tmp + "/evaluate"},
      {"diagnose " + sample("mems") + " --no-plots --out ", tmp + "/diagnose",
       "cannot write a temporary file in"},
      {"graft " + sample("tactical") + " --out ", tmp + "/graft"},
      {"simulate --config " + test::sourceDir() + "/configs/sim/sample_tactical.yaml --out ",
       tmp + "/simulate"},
  };
  for (const Cmd& c : cmds) {
    const test::CommandOutput r = test::runGraftnav(c.args + c.out, limit);
    SCOPED_TRACE(c.args);
    expectFailedCleanly(r, c.out, {"File too large", c.where.empty() ? c.out : c.where});
  }
}

// A full disk: a 64 KiB tmpfs filled up before the run (root), else the write failure is injected
// with a file-size limit as above.
TEST(Faults, FullDiskFailsWithErrnoTextAndLeavesNoFile) {
  const std::string dir = test::makeTempDir("fulldisk") + "/disk";
  fs::create_directories(dir);
  const TmpfsMount disk(dir, "size=64k");
  const bool mounted = disk.mounted();
  std::string prefix, expected;
  if (mounted) {
    fs::create_directories(dir + "/out");
    std::system(("dd if=/dev/zero of=" + dir + "/filler bs=4k count=64 > /dev/null 2>&1").c_str());
    expected = "No space left on device";
  } else {
    fs::create_directories(dir + "/out");
    prefix = "trap '' XFSZ; ulimit -f 0;";
    expected = "File too large";
  }
  const test::CommandOutput r = test::runGraftnav(
      "calibrate " + sample("tactical") + " --no-plots --out " + dir + "/out", prefix);
  expectFailedCleanly(r, dir + "/out", {expected, dir + "/out/calibration.yaml"});
}

// The disk fills up during the run (root only: 12 KiB left on a 64 KiB tmpfs; calibrate writes
// about 21 KiB): the files written before the failure are complete, byte for byte those of an
// unconstrained run, the one that failed is absent, no temporary file is left, and the exit code
// and message say what happened.
TEST(Faults, DiskFillingDuringTheRunLeavesOnlyCompleteFiles) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  const std::string ref = test::makeTempDir("fill_ref") + "/out";
  ASSERT_EQ(
      test::runGraftnav("calibrate " + sample("tactical") + " --no-plots --out " + ref).exit_code,
      0);
  const std::string dir = test::makeTempDir("fill") + "/disk";
  fs::create_directories(dir);
  const TmpfsMount disk(dir, "size=64k");
  ASSERT_TRUE(disk.mounted()) << std::strerror(errno);
  fs::create_directories(dir + "/out");
  std::system(("dd if=/dev/zero of=" + dir + "/filler bs=4k count=13 > /dev/null 2>&1").c_str());
  const test::CommandOutput r =
      test::runGraftnav("calibrate " + sample("tactical") + " --no-plots --out " + dir + "/out");
  EXPECT_NE(r.exit_code, 0) << r.text;
  EXPECT_NE(r.text.find("No space left on device"), std::string::npos) << r.text;
  const std::vector<std::string> left = filesIn(dir + "/out");
  EXPECT_FALSE(left.empty()) << "nothing fitted: the test no longer fills the disk halfway";
  for (const std::string& f : left) {
    EXPECT_NE(f[0], '.') << "temporary file left: " << f;
    EXPECT_EQ(readLines(dir + "/out/" + f), readLines(ref + "/" + f)) << f;
  }
  EXPECT_LT(left.size(), filesIn(ref).size());
}

// The library writer itself: a failed commit removes the temporary file, the old file survives.
TEST(Faults, AtomicFileKeepsThePreviousFileWhenAWriteFails) {
  const std::string dir = test::makeTempDir("atomic");
  const TmpfsMount disk(dir, "size=64k");
  if (!disk.mounted())
    GTEST_SKIP() << "needs root to mount a small tmpfs; the file-size-limit tests cover the rest";
  const std::string small = dir + "/result.txt";
  writeFileAtomically(small, "old\n");
  try {
    writeFileAtomically(small, std::string(200 * 1024, 'x'));
    ADD_FAILURE() << "a 200 KiB write onto a 64 KiB tmpfs succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(small), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_EQ(readLines(small), std::vector<std::string>{"old"});
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"result.txt"});
}

// A run killed with SIGKILL halfway through writing solution.nav (2.5 MB, written in 1 MiB
// chunks): the first chunk reaching the temporary file is the signal to kill. Afterwards the final
// name must not exist; only temporary files may be left behind.
TEST(Faults, SigkillHalfwayThroughAWriteLeavesNoPartialResult) {
  const std::string out = test::makeTempDir("sigkill") + "/out";
  fs::create_directories(out);
  const int ino = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  ASSERT_GE(ino, 0);
  ASSERT_GE(inotify_add_watch(ino, out.c_str(), IN_MODIFY), 0);
  const std::string bin = test::graftnavBinary(), cs = sample("tactical");
  std::vector<std::string> args = {bin, "navigate", cs, "--out", out, "--no-plots"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, bin.c_str(), &fa, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&fa);
  bool killed = false;
  char buf[4096] __attribute__((aligned(alignof(inotify_event))));
  for (int waited = 0; !killed && waited < 600; ++waited) {  // at most 60 s
    pollfd p{ino, POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    const ssize_t len = read(ino, buf, sizeof buf);
    for (ssize_t off = 0; off < len && !killed;) {
      const auto* ev = reinterpret_cast<const inotify_event*>(buf + off);
      if (ev->len > 0 && std::string(ev->name).rfind(".solution.nav.tmp.", 0) == 0) {
        kill(pid, SIGKILL);
        killed = true;
      }
      off += static_cast<ssize_t>(sizeof(inotify_event) + ev->len);
    }
  }
  int status = 0;
  waitpid(pid, &status, 0);
  close(ino);
  ASSERT_TRUE(killed) << "the writer never wrote into its temporary file";
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "the run ended before the kill";
  EXPECT_FALSE(fs::exists(out + "/solution.nav"));
  // A streamed run writes solution.nav, imu_errors.txt, state_std.txt and (against its truth)
  // errors.csv side by side: only their temporary files may be left, never a final name.
  for (const auto& f : filesIn(out)) {
    const bool tmp = f.rfind(".solution.nav.tmp.", 0) == 0 ||
                     f.rfind(".imu_errors.txt.tmp.", 0) == 0 ||
                     f.rfind(".state_std.txt.tmp.", 0) == 0 || f.rfind(".errors.csv.tmp.", 0) == 0;
    EXPECT_TRUE(tmp) << f;
  }
}

// docs/io.md promises that every writer goes through a temporary file: no source file other than
// the atomic writer opens a file for writing.
TEST(Faults, NoWriterBypassesAtomicFile) {
  const std::regex opens_for_writing(
      R"(std::ofstream|std::fstream|fmt::output_file|fopen\s*\([^;]*"[wa]|open\s*\([^;]*O_(WRONLY|RDWR|CREAT))");
  // A batch task's stdout and stderr are a live log of its child process, not a result: the
  // task database, written atomically, says whether it finished.
  const std::vector<std::string> allowed = {"core/io/src/atomic_file.cpp",
                                            "core/batch/src/child_process.cpp"};
  std::vector<std::string> offenders;
  for (const std::string top : {"apps", "core", "filters", "graph"}) {
    for (const auto& e : fs::recursive_directory_iterator(test::sourceDir() + "/" + top)) {
      const std::string p = e.path().string();
      const std::string rel = p.substr(test::sourceDir().size() + 1);
      if (!e.is_regular_file() || rel.find("/tests/") != std::string::npos) continue;
      if (e.path().extension() != ".cpp" && e.path().extension() != ".h") continue;
      if (std::find(allowed.begin(), allowed.end(), rel) != allowed.end()) continue;
      const auto lines = readLines(p);
      for (std::size_t i = 0; i < lines.size(); ++i)
        if (std::regex_search(lines[i], opens_for_writing))
          offenders.push_back(rel + ":" + std::to_string(i + 1));
    }
  }
  EXPECT_TRUE(offenders.empty()) << join(offenders);
}

}  // namespace
}  // namespace graftnav
