#include "fabkit/core/parallel.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
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

// The helper threads are kept between calls (a new thread can take milliseconds to be first
// scheduled): the helper of a second call has run pieces before, which a new thread has not
// (asked of a thread-local count, as a new thread may get a finished one's id).
TEST(Parallel, HelperThreadsAreKeptBetweenCalls) {
  start_helper_threads(2);
  thread_local int pieces_run = 0;
  const std::thread::id caller = std::this_thread::get_id();
  // The fewest pieces any helper of a call had run before its pieces of this call.
  auto helpers_experience = [&] {
    std::atomic<int> fewest{1 << 30};
    std::atomic<int> helper_pieces{0};
    run_in_parallel(4, 2, [&](int) {
      const int before = pieces_run++;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (std::this_thread::get_id() == caller) return;
      ++helper_pieces;
      int seen = fewest.load();
      while (before < seen && !fewest.compare_exchange_weak(seen, before)) {
      }
    });
    EXPECT_GT(helper_pieces.load(), 0) << "a helper took part";
    return fewest.load();
  };
  helpers_experience();
  EXPECT_GT(helpers_experience(), 0) << "the second call's helper is the first's";
}

// A piece that waits for an earlier one (step 1's starts wait for the verified start's plan)
// and calls inside calls (step 2's groups, each relaxing its candidates at once) finish: a piece
// is taken only after every earlier one was, each by a thread that runs it.
TEST(Parallel, NestedCallsAndPiecesThatWaitForEarlierOnesFinish) {
  std::atomic<int> inner_runs{0};
  for (int round = 0; round < 20; ++round) {
    run_in_parallel(3, 2, [&](int outer) {
      std::mutex mutex;
      std::condition_variable signal;
      bool first_done = false;
      run_in_parallel(2, 2, [&](int k) {
        if (k == 0) {
          {
            const std::lock_guard lock(mutex);
            first_done = true;
          }
          signal.notify_all();
        } else {
          std::unique_lock lock(mutex);
          signal.wait(lock, [&] { return first_done; });
        }
        ++inner_runs;
      });
      (void)outer;
    });
  }
  EXPECT_EQ(inner_runs.load(), 20 * 3 * 2);
}

// Several callers at once (the server's solves): each gets every index of its own call once.
TEST(Parallel, CallersOnSeveralThreadsAtOnce) {
  std::vector<std::vector<std::atomic<int>>> runs(6);
  for (auto& r : runs) r = std::vector<std::atomic<int>>(200);
  std::vector<std::thread> callers;
  for (std::size_t c = 0; c < runs.size(); ++c) {
    callers.emplace_back([&, c] {
      for (int repeat = 0; repeat < 5; ++repeat) {
        run_in_parallel(
            40, 3, [&](int i) { ++runs[c][static_cast<std::size_t>(repeat * 40 + i)]; });
      }
    });
  }
  for (std::thread& t : callers) t.join();
  for (const auto& r : runs)
    for (const std::atomic<int>& n : r) EXPECT_EQ(n.load(), 1);
}

TEST(Parallel, AFailedCallLeavesTheHelpersWorking) {
  EXPECT_THROW(run_in_parallel(10,
                               2,
                               [](int i) {
                                 if (i == 0) throw std::runtime_error("piece 0 failed");
                               }),
               std::runtime_error);
  std::vector<std::atomic<int>> runs(30);
  run_in_parallel(30, 2, [&](int i) { ++runs[static_cast<std::size_t>(i)]; });
  for (const std::atomic<int>& r : runs) EXPECT_EQ(r.load(), 1);
}

// A child forked after the helpers started (Python's multiprocessing does) has none of them:
// its own calls start their own instead of waiting for ever on threads that are not there.
TEST(Parallel, AForkedChildStartsItsOwnHelpers) {
  start_helper_threads(2);
  std::atomic<int> ran{0};
  run_in_parallel(4, 2, [&](int) { ++ran; });
  ASSERT_EQ(ran.load(), 4);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    alarm(20);  // a child that waits for ever is killed, and the test fails
    std::atomic<int> pieces{0};
    run_in_parallel(8, 2, [&](int) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      ++pieces;
    });
    _exit(pieces.load() == 8 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status)) << "the child did not finish (signal " << WTERMSIG(status) << ")";
  EXPECT_EQ(WEXITSTATUS(status), 0);
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
