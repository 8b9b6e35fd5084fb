#include "job_queue.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <chrono>

#include "fabkit/core/json.h"

namespace fabkit::server {

namespace {

using Clock = std::chrono::steady_clock;

JobAnswer refusal(int status, const std::string& message) {
  return {status, dump_json(Json{{"error", message}, {"diagnostics", Json::array()}})};
}

}  // namespace

struct JobQueue::Job {
  Work work;
  std::promise<JobAnswer> promise;
  std::shared_ptr<std::atomic<bool>> cancelled = std::make_shared<std::atomic<bool>>(false);
  Clock::time_point queued = Clock::now();
};

JobQueue::JobQueue(Options options) : options_(options) {
  const int n = std::max(1, options_.workers);
  for (int i = 0; i < n; ++i) workers_.emplace_back([this] { work(); });
}

JobQueue::~JobQueue() {
  stop();
}

std::optional<JobQueue::Ticket> JobQueue::submit(Work work) {
  auto job = std::make_shared<Job>();
  job->work = std::move(work);
  Ticket ticket{job->promise.get_future().share(), job->cancelled};
  {
    std::lock_guard lock(mutex_);
    if (stopping_ || queue_.size() + running_ >= options_.max_pending) return std::nullopt;
    queue_.push_back(std::move(job));
  }
  wake_.notify_one();
  return ticket;
}

std::size_t JobQueue::pending() const {
  std::lock_guard lock(mutex_);
  return queue_.size() + running_;
}

void JobQueue::stop() {
  std::deque<std::shared_ptr<Job>> dropped;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && workers_.empty()) return;
    stopping_ = true;
    dropped.swap(queue_);
  }
  wake_.notify_all();
  for (const auto& job : dropped) {
    job->promise.set_value(refusal(503, "the server is stopping"));
  }
  for (std::thread& t : workers_) {
    if (t.joinable()) t.join();
  }
  workers_.clear();
}

namespace {
thread_local bool t_on_worker = false;
}  // namespace

bool JobQueue::on_worker_thread() {
  return t_on_worker;
}

void JobQueue::work() {
  t_on_worker = true;
#ifdef __linux__
  // Lower priority for the heavy work, so the request threads get the CPU when they need it.
  if (options_.nice > 0) {
    ::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), options_.nice);
  }
#endif
  while (true) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping
      job = std::move(queue_.front());
      queue_.pop_front();
      ++running_;
    }
    const double waited = std::chrono::duration<double>(Clock::now() - job->queued).count();
    if (*job->cancelled) {
      job->promise.set_value(refusal(503, "cancelled: the client left"));
    } else if (waited > options_.max_wait_s) {
      job->promise.set_value(refusal(
          503,
          fmt::format("the server is busy: this request waited {:.0f} s for its turn; try again",
                      waited)));
    } else {
      try {
        job->promise.set_value(job->work());
      } catch (const std::exception&) {
        job->promise.set_value(refusal(500, "internal error while answering the request"));
      } catch (...) {
        job->promise.set_value(refusal(500, "internal error while answering the request"));
      }
    }
    std::lock_guard lock(mutex_);
    --running_;
  }
}

}  // namespace fabkit::server
