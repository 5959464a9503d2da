// The batch knows the commands only through its table; every flag it lets a group pass, and every
// flag it sets itself, must be one the command takes (its --help lists it).
#include <gtest/gtest.h>

#include <regex>

#include "batch_test_util.h"
#include "graftnav/batch/command_table.h"

namespace graftnav {
namespace {

bool helpHasFlag(const std::string& help, const std::string& flag) {
  return std::regex_search(help, std::regex("(^|[ ,])" + flag + "([ ,=\\n]|$)"));
}

TEST(BatchCommandTable, EveryFlagIsOneTheCommandTakes) {
  for (BatchCommand c : allBatchCommands()) {
    const BatchCommandSpec& spec = batchCommandSpec(c);
    const std::string name = batchCommandName(c);
    EXPECT_EQ(parseBatchCommand(name), c);
    const auto r = batch_test::graftnav(name + " --help");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::vector<std::string> flags{"--out", "--run-config", "--no-plots", "--estimator"};
    if (spec.takes_seed) flags.push_back("--seed");
    if (spec.takes_jobs) flags.push_back("--jobs");
    for (const auto& f : spec.flags) flags.push_back("--" + f.name);
    for (const auto& f : flags) EXPECT_TRUE(helpHasFlag(r.output, f)) << name << " " << f;
    for (const auto& f : spec.required_flags) EXPECT_TRUE(findFlag(spec, f)) << name << " " << f;
  }
  EXPECT_FALSE(parseBatchCommand("batch"));
  EXPECT_EQ(batchCommandList(), "navigate, compare, real, real-sg, evaluate, diagnose");
}

}  // namespace
}  // namespace graftnav
