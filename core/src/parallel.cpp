#include "fabkit/core/parallel.h"

#include <algorithm>
#include <atomic>
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

// One call's pieces of work, shared by its caller and the helpers it enlisted. The caller
// returns only once every enlisted helper has left it.
struct Batch {
  int count = 0;
  const std::function<void(int)>* work = nullptr;
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;  // guards first_error and remaining
  std::exception_ptr first_error;
  int remaining = 0;  // helpers enlisted that have not left
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
    // Notified under the lock: the caller may destroy the batch as soon as it can see
    // remaining at 0, which is only after this unlocks.
    const std::lock_guard lock(mutex);
    if (--remaining == 0) left.notify_one();
  }
};

// Threads kept for the whole process and handed each call's batch. A new thread is slow to
// start on some machines: on the two-core VM the benchmarks run on, one began 0.5–5 ms after it
// was created (at the other core's next scheduler tick) while a thread already running there,
// asleep on a condition variable, woke within 0.02 ms — and the solver's parallel sections are
// a few milliseconds long. Never destroyed: helpers wait in it until the process ends.
class HelperPool {
 public:
  static HelperPool& instance() {
    static HelperPool* const pool = new HelperPool;
    return *pool;
  }

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
      h->batch = &batch;
      h->wake.notify_one();
      ++enlisted;
    }
    return enlisted;
  }

 private:
  struct Helper {
    Batch* batch = nullptr;  // the batch handed to it; null while idle
    std::condition_variable wake;
  };

  // Called with mutex_ held; the new helper is idle.
  bool start_one() {
    auto helper = std::make_unique<Helper>();
    Helper* h = helper.get();
    try {
      std::thread([this, h] { serve(*h); }).detach();
    } catch (const std::system_error&) {
      return false;  // no more threads: the caller does the work itself
    }
    all_.push_back(std::move(helper));
    idle_.push_back(h);
    return true;
  }

  void serve(Helper& h) {
    std::unique_lock lock(mutex_);
    for (;;) {
      h.wake.wait(lock, [&] { return h.batch != nullptr; });
      Batch* batch = h.batch;
      lock.unlock();
      batch->take();
      lock.lock();
      h.batch = nullptr;
      idle_.push_back(&h);
      lock.unlock();
      batch->leave();  // the last touch of the batch
      lock.lock();
    }
  }

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
  {
    std::unique_lock lock(batch.mutex);
    batch.left.wait(lock, [&] { return batch.remaining == 0; });
  }
  if (batch.first_error) std::rethrow_exception(batch.first_error);
}

}  // namespace fabkit
