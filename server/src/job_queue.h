#pragma once
// The server's heavy work (checks and solves) runs here, on a few worker threads of lower CPU
// priority with a bounded queue, never on the threads that read requests: light requests (the
// parts library, meshes) stay fast however many solves are waiting, and a burst of solves
// gets "busy, try again" instead of unbounded memory and waiting.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace fabkit::server {

/// What a job answers: an HTTP status, a body and its media type.
struct JobAnswer {
  int status = 500;
  std::string body;
  std::string content_type = "application/json";
};

class JobQueue {
 public:
  struct Options {
    int workers = 1;               ///< jobs run at once
    std::size_t max_pending = 64;  ///< jobs queued or running; more are refused
    double max_wait_s = 120;       ///< a job that waited longer is answered 503 without running
    int nice = 10;                 ///< the workers' CPU niceness (Linux; 0: as the server)
  };
  using Work = std::function<JobAnswer()>;
  struct Ticket {
    std::shared_future<JobAnswer> answer;
    /// Set when nobody waits for the answer any more (the client left): not run if not started.
    std::shared_ptr<std::atomic<bool>> cancelled;
  };

  explicit JobQueue(Options options);
  ~JobQueue();
  JobQueue(const JobQueue&) = delete;
  JobQueue& operator=(const JobQueue&) = delete;

  /// Queues `work`; nullopt when max_pending jobs are already queued or running, or stopped.
  std::optional<Ticket> submit(Work work);
  /// Refuses new jobs, answers the queued ones with 503 and waits for the running ones.
  void stop();
  /// Jobs queued or running.
  std::size_t pending() const;
  bool stopping() const { return stopping_; }
  /// Whether the calling thread is one of a JobQueue's workers.
  static bool on_worker_thread();
  const Options& options() const { return options_; }

 private:
  struct Job;
  void work();

  Options options_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::size_t running_ = 0;
  std::atomic<bool> stopping_{false};
  std::vector<std::thread> workers_;
};

}  // namespace fabkit::server
