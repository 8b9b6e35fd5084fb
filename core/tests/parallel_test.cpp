#include "fabkit/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace fabkit {
namespace {

TEST(Parallel, EveryIndexRunsExactlyOnce) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> runs(100);
    run_in_parallel(100, threads, [&](int i) { ++runs[static_cast<std::size_t>(i)]; });
    for (const std::atomic<int>& r : runs) EXPECT_EQ(r.load(), 1) << threads << " threads";
  }
}

TEST(Parallel, WorkIsSharedBetweenThreads) {
  // Each piece takes long enough that one thread cannot take them all before the other starts.
  std::mutex mutex;
  std::set<std::thread::id> ids;
  run_in_parallel(4, 2, [&](int) {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    const std::lock_guard lock(mutex);
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(ids.size(), 2u);
  EXPECT_TRUE(ids.count(std::this_thread::get_id())) << "the calling thread works too";
}

TEST(Parallel, AnExceptionReachesTheCaller) {
  std::atomic<int> ran{0};
  EXPECT_THROW(run_in_parallel(50,
                               2,
                               [&](int i) {
                                 ++ran;
                                 std::this_thread::sleep_for(std::chrono::milliseconds(1));
                                 if (i == 3) throw std::runtime_error("piece 3 failed");
                               }),
               std::runtime_error);
  EXPECT_LT(ran.load(), 50) << "no further pieces are handed out after a failure";
}

TEST(Parallel, NothingToDoAndThreadCounts) {
  bool called = false;
  run_in_parallel(0, 4, [&](int) { called = true; });
  EXPECT_FALSE(called);
  EXPECT_EQ(thread_count(3), 3);
  EXPECT_GE(thread_count(0), 1);
}

}  // namespace
}  // namespace fabkit
