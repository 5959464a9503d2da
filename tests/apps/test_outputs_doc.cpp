// docs/outputs.md against what the commands write: every file a run leaves in its output folder
// has a row in the command's section, and every column of its header line is named in that row.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The text of "## <command>" up to the next "## ".
std::string section(const std::string& doc, const std::string& command) {
  const std::string head = "\n## " + command + "\n";
  const size_t a = doc.find(head);
  if (a == std::string::npos) return {};
  const size_t b = doc.find("\n## ", a + head.size());
  return doc.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

std::string rowFor(const std::string& sec, const std::string& name) {
  std::istringstream in(sec);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("|", 0) == 0 && line.find("`" + name + "`") != std::string::npos) return line;
  return {};
}

// Column names of a .csv header, or of a '#' header line of a .txt table; empty otherwise.
std::vector<std::string> headerColumns(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> cols;
  std::string tok;
  if (file.extension() == ".csv") {
    std::istringstream ss(line);
    while (std::getline(ss, tok, ',')) cols.push_back(tok);
  } else if (file.extension() == ".txt" && line.rfind("#", 0) == 0) {
    std::istringstream ss(line.substr(1));
    while (ss >> tok) cols.push_back(tok);
  }
  return cols;
}

// Names the doc uses for per-estimator folders and columns and for copied peer configs.
std::string normalize(std::string s) {
  for (const std::string e : {"ekf", "rts"}) {
    if (s.rfind(e + "/", 0) == 0) s = "<estimator>/" + s.substr(e.size() + 1);
    if (s.rfind(e + "_", 0) == 0) s = "<estimator>_" + s.substr(e.size() + 1);
  }
  if (s.rfind("source/", 0) == 0) s = "source/<name>.yaml";
  return s;
}

void expectDocumented(const std::string& command, const std::string& out_dir) {
  const std::string sec = section(readAll(test::sourceDir() + "/docs/outputs.md"), command);
  ASSERT_FALSE(sec.empty()) << "docs/outputs.md has no section '## " << command << "'";
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(out_dir)) {
    if (e.is_directory() || e.path().filename() == "log.txt") continue;
    ++files;
    const std::string name = normalize(e.path().lexically_relative(out_dir).generic_string());
    const std::string row = rowFor(sec, name);
    EXPECT_FALSE(row.empty()) << command << " writes " << name << ", not in docs/outputs.md";
    for (const auto& col : headerColumns(e.path())) {
      EXPECT_NE(row.find("`" + normalize(col) + "`"), std::string::npos)
          << command << ": column '" << col << "' of " << name << " not in docs/outputs.md";
    }
  }
  EXPECT_GT(files, 0) << command << " wrote nothing into " << out_dir;
}

int run(const std::string& args, const std::string& log) {
  return std::system((test::graftnavBinary() + " " + args + " > " + log + " 2>&1").c_str());
}

class OutputsDoc : public ::testing::Test {
 protected:
  std::string sample_ = test::sourceDir() + "/data/sample_mems";
  std::string dir_ = test::makeTempDir("outputs_doc");
  // `command` may hold a sub-subcommand ("import kf-gins"); its first word names the section.
  void runAndCheck(const std::string& command, const std::string& args) {
    const std::string word = command.substr(0, command.find(' '));
    const std::string out = dir_ + "/" + word;
    ASSERT_EQ(run(command + " " + args + " --out " + out, out + ".log"), 0)
        << readAll(out + ".log");
    expectDocumented(word, out);
  }
};

TEST_F(OutputsDoc, Navigate) {
  runAndCheck("navigate", sample_ + " --imu tested --no-plots --run-config " + test::sourceDir() +
                              "/configs/navigate.yaml");
}

TEST_F(OutputsDoc, Compare) { runAndCheck("compare", sample_ + " --estimator ekf,rts --no-plots"); }

TEST_F(OutputsDoc, CalibrateGraftEvaluate) {
  runAndCheck("calibrate", sample_ + " --no-plots");
  runAndCheck("graft", sample_);
  runAndCheck("evaluate", sample_ + " --no-plots --run-config " + test::sourceDir() +
                              "/configs/evaluate_sample.yaml");
}

TEST_F(OutputsDoc, Import) {
  std::ofstream(dir_ + "/kf.yaml")
      << "imupath: " << sample_ << "/field/tested_imu.txt\ngnsspath: " << sample_
      << "/field/gnss.pos\nimudatarate: 50\nstarttime: 456340\ninitpos: [30.44, 114.47, 21]\n"
         "initatt: [0, 0, 180]\nimunoise: {arw: 0.15, vrw: 0.06, gbstd: 10, abstd: 1000, "
         "corrtime: 1}\n";
  runAndCheck("import kf-gins", dir_ + "/kf.yaml --reference " + sample_ + "/field/truth.nav");
}

TEST_F(OutputsDoc, Real) {
  const std::string real_case = test::sharedDir() + "/data/real/yandld_20220405_rtk";
  GRAFTNAV_REQUIRE_SHARED_PATH(real_case);
  const std::string cfg = test::sourceDir() + "/configs/real";
  runAndCheck("real", real_case +
                          " --imu tested --estimator ekf --no-plots --latency-scan --run-config " +
                          cfg + "/yandld.yaml --profile " + cfg + "/yandld_mems.yaml");
}

}  // namespace
}  // namespace graftnav
