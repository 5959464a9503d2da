// Tasks as child processes: exit codes and crashes stay with the child, its output lands in its
// files, and the kernel's measure of its peak memory and CPU time comes back.
#include "graftnav/batch/child_process.h"

#include <gtest/gtest.h>

#include "batch_test_util.h"

namespace graftnav {
namespace {
using batch_test::readFile;
using batch_test::writeFile;

TEST(ChildProcess, ExitCodeOutputFilesAndFolder) {
  const std::string dir = test::makeTempDir("child_exit");
  const ChildResult r =
      runChildProcess({"/bin/sh", "-c", "pwd; echo 'first problem' >&2; echo last >&2; exit 3"},
                      dir, dir + "/out.txt", dir + "/err.txt");
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.describe(), "exit code 3");
  EXPECT_EQ(readFile(dir + "/out.txt"), dir + "\n");
  EXPECT_EQ(lastLines(dir + "/err.txt", 1), "last");
  EXPECT_EQ(lastLines(dir + "/err.txt", 5), "first problem\nlast");
  EXPECT_GE(r.wall_seconds, 0.0);
}

TEST(ChildProcess, ACrashIsTheChildsOwn) {
  const std::string dir = test::makeTempDir("child_crash");
  const ChildResult r = runChildProcess({"/bin/sh", "-c", "echo dying >&2; kill -SEGV $$"}, dir,
                                        dir + "/out.txt", dir + "/err.txt");
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.signal, 11);
  EXPECT_NE(r.describe().find("killed by signal 11"), std::string::npos) << r.describe();
  EXPECT_EQ(lastLines(dir + "/err.txt", 3), "dying");
  // The parent goes on: another child runs normally.
  EXPECT_TRUE(runChildProcess({"/bin/true"}, dir, dir + "/o", dir + "/e").ok());
}

TEST(ChildProcess, ProgramThatCannotRunExitsWith127AndSaysWhy) {
  const std::string dir = test::makeTempDir("child_missing");
  const ChildResult r =
      runChildProcess({dir + "/no_such_program"}, dir, dir + "/out.txt", dir + "/err.txt");
  EXPECT_EQ(r.exit_code, 127);
  EXPECT_NE(readFile(dir + "/err.txt").find("cannot execute"), std::string::npos);
}

TEST(ChildProcess, PeakMemoryAndCpuTimeAreTheChilds) {
  const std::string dir = test::makeTempDir("child_rss");
  // 200 MB written (so resident), and about 0.3 s of CPU.
  const ChildResult big =
      runChildProcess({"/usr/bin/python3", "-c",
                       "import time\nb = b'x' * 200_000_000\nt = time.process_time()\n"
                       "while time.process_time() - t < 0.3: pass\nprint(len(b))"},
                      dir, dir + "/out.txt", dir + "/err.txt");
  ASSERT_TRUE(big.ok()) << readFile(dir + "/err.txt");
  EXPECT_GT(big.peak_rss_mb, 190.0);
  EXPECT_LT(big.peak_rss_mb, 400.0);
  EXPECT_GT(big.cpu_seconds, 0.3);
  const ChildResult small = runChildProcess({"/bin/true"}, dir, dir + "/o", dir + "/e");
  EXPECT_LT(small.peak_rss_mb, 20.0) << "the parent's memory is not the child's";
}

TEST(ChildProcess, RunProgramCapturesOutput) {
  const auto [rc, out] = runProgram({"sh", "-c", "echo hello; exit 4"}, "/");
  EXPECT_EQ(rc, 4);
  EXPECT_EQ(out, "hello\n");
  EXPECT_EQ(runProgram({"no-such-program-here"}, "/").first, 127);
}

}  // namespace
}  // namespace graftnav
