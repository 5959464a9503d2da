#include "graftnav/parallel/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace graftnav {
namespace {

TEST(WorkerPool, WorkerCountIsBoundedByTheItemsAndAtLeastOne) {
  EXPECT_EQ(workerCount(10, 3), 3);
  EXPECT_EQ(workerCount(2, 8), 2);
  EXPECT_EQ(workerCount(0, 4), 1);
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_EQ(workerCount(1000, 0), hw);
  EXPECT_THROW(workerCount(5, -1), std::invalid_argument);
}

TEST(WorkerPool, EveryItemRunsOnceAndEachDoneCallSeesTheRunningCount) {
  for (int jobs : {1, 2, 7, 0}) {
    for (std::size_t count : {0u, 1u, 3u, 200u}) {
      std::vector<int> runs(count, 0);
      std::vector<int> done_seen(count + 1, 0);
      std::size_t calls = 0;  // only touched inside on_done, which the pool serializes
      parallelFor(
          count, jobs, [&](std::size_t i) { ++runs[i]; },
          [&](std::size_t index, std::size_t done) {
            ASSERT_LT(index, count);
            ASSERT_GE(done, 1u);
            ASSERT_LE(done, count);
            ++done_seen[done];
            ++calls;
          });
      EXPECT_EQ(calls, count) << "jobs " << jobs;
      for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(runs[i], 1) << i << " jobs " << jobs;
      for (std::size_t d = 1; d <= count; ++d) EXPECT_EQ(done_seen[d], 1) << d;
    }
  }
}

// Two items that wait for each other finish only when they run at the same time.
TEST(WorkerPool, TwoJobsRunTwoItemsAtOnce) {
  std::atomic<int> arrived{0};
  std::atomic<bool> timed_out{false};
  parallelFor(2, 2, [&](std::size_t) {
    ++arrived;
    const auto t0 = std::chrono::steady_clock::now();
    while (arrived.load() < 2) {
      if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(20)) {
        timed_out = true;
        return;
      }
      std::this_thread::yield();
    }
  });
  EXPECT_FALSE(timed_out) << "the second item never started while the first ran";
}

TEST(WorkerPool, TheFirstFailureStopsTheRestAndIsRethrown) {
  std::vector<int> runs(50, 0);
  try {
    parallelFor(50, 1, [&](std::size_t i) {
      ++runs[i];
      if (i == 10) throw std::runtime_error("item 10 failed");
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 10 failed");
  }
  for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i], i <= 10 ? 1 : 0) << i;

  // On several threads the items already running finish; far fewer than all start.
  std::atomic<int> started{0};
  EXPECT_THROW(parallelFor(1000, 4,
                           [&](std::size_t i) {
                             ++started;
                             if (i == 0) throw std::logic_error("first");
                             std::this_thread::sleep_for(std::chrono::milliseconds(1));
                           }),
               std::logic_error);
  EXPECT_LT(started.load(), 1000);
}

TEST(WorkerPool, AFailingDoneCallbackIsRethrownToo) {
  EXPECT_THROW(parallelFor(
                   4, 2, [](std::size_t) {},
                   [](std::size_t, std::size_t done) {
                     if (done == 2) throw std::runtime_error("report failed");
                   }),
               std::runtime_error);
}

}  // namespace
}  // namespace graftnav
