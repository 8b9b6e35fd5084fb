#include "fabkit/core/parallel.h"

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace fabkit {

int thread_count(int threads) {
  if (threads > 0) return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

namespace {

// How long a waiting thread polls before it sleeps: a helper between two calls, a caller for
// its helpers. On the two-core VM the benchmarks run on, a thread asleep on a condition
// variable usually woke within 0.1 ms but one wake in six took 1-4 ms (at the other core's
// next scheduler tick), and the solver's parallel sections, and the gaps between them, are a
// few milliseconds long. Polling yields, so any other thread that is ready runs first.
constexpr std::chrono::milliseconds kPollFor{20};

// Polls `ready` for up to kPollFor; whether it became true.
template <typename Ready>
bool poll(Ready ready) {
  const auto until = std::chrono::steady_clock::now() + kPollFor;
  for (int i = 0;; ++i) {
    if (ready()) return true;
    if ((i & 63) == 63 && std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::yield();
  }
}

// A new thread is queued on its creator's core, where it waits until the scheduler moves it
// (up to a tick: 4 ms on the VM above, where a third of fabkit solves' first parallel section
// began that late). A helper is started on another of the cores its creator may use and, once
// running, lets itself run on any of them again.
class Cores {
 public:
  Cores() {
#ifdef __linux__
    known_ = sched_getaffinity(0, sizeof allowed_, &allowed_) == 0;
#endif
  }
  // Sends `t`, not yet running, to a core other than the calling thread's.
  void start_elsewhere(std::thread& t) const {
#ifdef __linux__
    const int here = sched_getcpu();
    if (!known_ || here < 0) return;
    cpu_set_t others = allowed_;
    CPU_CLR(here, &others);
    if (CPU_COUNT(&others) > 0) pthread_setaffinity_np(t.native_handle(), sizeof others, &others);
#else
    (void)t;
#endif
  }
  // Lets the calling thread run on every core its creator could.
  void run_anywhere() const {
#ifdef __linux__
    if (known_) pthread_setaffinity_np(pthread_self(), sizeof allowed_, &allowed_);
#endif
  }

 private:
#ifdef __linux__
  cpu_set_t allowed_{};
  bool known_ = false;
#endif
};

// One call's pieces of work, shared by its caller and the helpers it enlisted. The caller
// returns only once every enlisted helper has left it.
struct Batch {
  int count = 0;
  const std::function<void(int)>* work = nullptr;
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;  // guards first_error; remaining changes under it
  std::exception_ptr first_error;
  std::atomic<int> remaining{0};  // helpers enlisted that have not left
  std::condition_variable left;

  void take() {
    for (int i = next++; i < count && !failed.load(); i = next++) {
      try {
        (*work)(i);
      } catch (...) {
        const std::lock_guard lock(mutex);
        if (!first_error) first_error = std::current_exception();
        failed = true;
      }
    }
  }

  void leave() {
    // Under the lock, which the caller takes before it returns: the batch outlives this.
    const std::lock_guard lock(mutex);
    if (--remaining == 0) left.notify_one();
  }

  void wait_for_helpers() {
    if (!poll([&] { return remaining.load() == 0; })) {
      std::unique_lock lock(mutex);
      left.wait(lock, [&] { return remaining.load() == 0; });
      return;
    }
    const std::lock_guard lock(mutex);  // the last helper has let go of it
  }
};

// Threads kept for the whole process and handed each call's batch: a new thread is slow to
// start on some machines (on the VM above one began 0.5-5 ms after it was created). Never
// destroyed: helpers wait in it until the process ends.
class HelperPool {
 public:
  static HelperPool& instance() { return *current(); }

 private:
  // A forked child has none of its parent's threads (a Python program's multiprocessing, for
  // one): it gets a pool of its own, empty, and the parent's is left alone (its lock may have
  // been held by a thread that does not exist there).
  static HelperPool*& current() {
    static HelperPool* pool = [] {
#ifdef __linux__
      pthread_atfork(nullptr, nullptr, [] { current() = new HelperPool; });
#endif
      return new HelperPool;
    }();
    return pool;
  }

 public:
  void ensure(int helpers) {
    const std::lock_guard lock(mutex_);
    while (static_cast<int>(all_.size()) < helpers && start_one()) {
    }
  }

  // Hands `batch` to up to `wanted` helpers, idle ones first, new ones after; returns how many
  // took it (fewer only when no thread could be started).
  int enlist(Batch& batch, int wanted) {
    const std::lock_guard lock(mutex_);
    int enlisted = 0;
    while (enlisted < wanted) {
      if (idle_.empty() && !start_one()) break;
      Helper* h = idle_.back();
      idle_.pop_back();
      h->batch.store(&batch);
      h->wake.notify_one();
      ++enlisted;
    }
    return enlisted;
  }

 private:
  struct Helper {
    std::atomic<Batch*> batch{nullptr};  // the batch handed to it (under mutex_); null if idle
    std::condition_variable wake;
    std::atomic<bool> placed{false};  // sent to its core: it may undo that now
  };

  // Called with mutex_ held; the new helper is idle.
  bool start_one() {
    all_.push_back(std::make_unique<Helper>());  // owned before its thread can use it
    Helper* h = all_.back().get();
    try {
      std::thread helper_thread([this, h] { serve(*h); });
      cores_.start_elsewhere(helper_thread);
      h->placed = true;
      helper_thread.detach();
    } catch (const std::system_error&) {
      all_.pop_back();
      return false;  // no more threads: the caller does the work itself
    }
    idle_.push_back(h);
    return true;
  }

  void serve(Helper& h) {
    // Not before its creator has placed it (else that would pin it for good).
    while (!h.placed.load()) std::this_thread::yield();
    cores_.run_anywhere();
    for (;;) {
      if (!poll([&] { return h.batch.load() != nullptr; })) {
        std::unique_lock lock(mutex_);
        h.wake.wait(lock, [&] { return h.batch.load() != nullptr; });
      }
      Batch* batch = h.batch.load();
      batch->take();
      {
        const std::lock_guard lock(mutex_);
        h.batch.store(nullptr);
        idle_.push_back(&h);
      }
      batch->leave();  // the last touch of the batch
    }
  }

  const Cores cores_;  // those of the thread that first used the pool
  std::mutex mutex_;
  std::vector<std::unique_ptr<Helper>> all_;
  std::vector<Helper*> idle_;
};

}  // namespace

void start_helper_threads(int threads) {
  const int helpers = thread_count(threads) - 1;
  if (helpers > 0) HelperPool::instance().ensure(helpers);
}

void run_in_parallel(int count, int threads, const std::function<void(int)>& work) {
  if (count <= 0) return;
  const int workers = std::min(thread_count(threads), count);
  Batch batch;
  batch.count = count;
  batch.work = &work;
  if (workers > 1) {
    // remaining is set before any helper can leave: under the batch's lock, released only
    // once the helpers have it.
    std::unique_lock lock(batch.mutex);
    batch.remaining = HelperPool::instance().enlist(batch, workers - 1);
  }
  batch.take();
  batch.wait_for_helpers();
  if (batch.first_error) std::rethrow_exception(batch.first_error);
}

}  // namespace fabkit
