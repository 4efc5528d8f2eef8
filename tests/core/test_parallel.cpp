// parallel_for (core/parallel.hpp): every task runs once and writes its own slot, whatever the thread count; the first
// exception stops the loop (no further task starts) and is rethrown once — a refused work estimate thrown from a
// progress callback must stop the work, not let the other tasks run on for minutes.
#include "geartopo/core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using geartopo::parallel_for;

TEST(ParallelFor, EveryTaskRunsOnceAtAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<int> runs(1000, 0);
    parallel_for(static_cast<int>(runs.size()), threads, [&](int i) { runs[static_cast<size_t>(i)] += i + 1; });
    for (size_t i = 0; i < runs.size(); ++i) ASSERT_EQ(runs[i], static_cast<int>(i) + 1) << threads << " threads";
  }
}

TEST(ParallelFor, TheFirstExceptionStopsTheLoopAndIsRethrown) {
  for (int threads : {1, 2, 4}) {
    std::atomic<int> started{0};
    const int count = 1000;
    EXPECT_THROW(parallel_for(count, threads,
                              [&](int i) {
                                ++started;
                                if (i == 0) throw std::runtime_error("refused");
                                std::this_thread::sleep_for(std::chrono::milliseconds(1));
                              }),
                 std::runtime_error);
    // Task 0 is the first one taken and throws at once; the other threads finish the task they hold (1 ms each)
    // and take no more. Without the stop all 1000 ran (≈ 1 s per thread).
    EXPECT_LE(started.load(), 4 * threads) << threads << " threads";
  }
}
