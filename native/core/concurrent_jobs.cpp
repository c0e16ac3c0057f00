#include "core/concurrent_jobs.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

namespace developable {
namespace {

struct Report {
  double fraction;
  const char* stage;
};

// What the threads share: the next job to take, each job's reports not yet
// passed on, which jobs have ended, and the stop every job hears at its next
// report.
struct Relay {
  explicit Relay(size_t jobs) : reports(jobs), ended(jobs, false) {}

  std::atomic<size_t> next_job{0};
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::deque<Report>> reports;
  std::vector<bool> ended;
  std::atomic<bool> stop{false};
};

// The progress callback of a job: its report is queued for the calling
// thread, and the answer is only "stop?". On the calling thread the queue is
// passed on at once as far as the job order allows (`pass_on`).
struct QueuedProgress {
  Relay* relay;
  size_t job;
  const std::function<void()>* pass_on;  // the calling thread's, else null

  static bool call(double fraction, const char* stage, void* user) {
    const auto* self = static_cast<const QueuedProgress*>(user);
    {
      const std::lock_guard<std::mutex> lock(self->relay->mutex);
      self->relay->reports[self->job].push_back({fraction, stage});
    }
    if (self->pass_on)
      (*self->pass_on)();
    else
      self->relay->changed.notify_all();
    return !self->relay->stop.load();
  }
};

// The calling thread's core counted spare while it waits for other threads
// (their work may take it), counted back in however the wait ends.
class IdleWhileWaiting {
 public:
  explicit IdleWhileWaiting(SpareCores* spare) : spare_(spare) {
    if (spare_) spare_->stop_working();
  }
  ~IdleWhileWaiting() {
    if (spare_) spare_->start_working();
  }
  IdleWhileWaiting(const IdleWhileWaiting&) = delete;
  IdleWhileWaiting& operator=(const IdleWhileWaiting&) = delete;

 private:
  SpareCores* spare_;
};

bool is_cancel(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const EngineError& e) {
    return e.status() == Status::cancelled;
  } catch (...) {
    return false;
  }
}

}  // namespace

unsigned thread_count(int threads) {
  return threads > 0 ? static_cast<unsigned>(threads) : std::max(1u, std::thread::hardware_concurrency());
}

SpareCores::SpareCores(int threads) : spare_(static_cast<int>(thread_count(threads)) - 1) {}

unsigned SpareCores::take(unsigned most) {
  int spare = spare_.load();
  while (spare > 0 && most > 0) {
    const int taken = std::min(spare, static_cast<int>(most));
    if (spare_.compare_exchange_weak(spare, spare - taken)) return static_cast<unsigned>(taken);
  }
  return 0;
}

void SpareCores::give_back(unsigned count) { spare_ += static_cast<int>(count); }

void run_concurrently(const std::vector<Job>& jobs, int threads, const Progress& progress, SpareCores* spare) {
  const size_t n = jobs.size();
  if (n == 0) return;
  const size_t helpers = std::min<size_t>(thread_count(threads), n) - 1;  // threads besides the calling one

  Relay relay(n);
  std::vector<std::exception_ptr> errors(n);
  const double share = 1.0 / static_cast<double>(n);

  // Passes the queued reports on to the callback, job by job in order, as
  // far as the jobs have ended: the calling thread only. A cancel stops
  // every job at its next report and the rest of the reports are dropped.
  size_t relayed = 0;  // the jobs whose reports have all been passed on
  std::exception_ptr cancelled;
  const std::function<void()> pass_on = [&] {
    while (relayed < n) {
      std::deque<Report> batch;
      bool ended = false;
      {
        const std::lock_guard<std::mutex> lock(relay.mutex);
        batch.swap(relay.reports[relayed]);
        ended = relay.ended[relayed];
      }
      const Progress own_share =
          progress.sub(share * static_cast<double>(relayed), share * static_cast<double>(relayed + 1));
      for (const Report& r : batch) {
        if (cancelled || relay.stop) break;
        try {
          own_share.report(r.fraction, r.stage);
        } catch (...) {
          cancelled = std::current_exception();
          relay.stop = true;
        }
      }
      if (!ended) return;
      ++relayed;
    }
  };

  // A job's callback, set by the thread that takes it.
  std::vector<QueuedProgress> queued(n);
  // Every thread takes the next job not yet taken until none is left, so a
  // long job does not hold up the short ones behind it (which thread runs a
  // job does not change its result).
  const auto take_jobs = [&](bool calling_thread) {
    for (size_t k = relay.next_job++; k < n; k = relay.next_job++) {
      if (!relay.stop) {
        try {
          queued[k] = {&relay, k, calling_thread ? &pass_on : nullptr};
          jobs[k](Progress{&QueuedProgress::call, &queued[k], 0.0, 1.0});
        } catch (...) {
          errors[k] = std::current_exception();
          relay.stop = true;
        }
      }
      {
        const std::lock_guard<std::mutex> lock(relay.mutex);
        relay.ended[k] = true;
      }
      if (calling_thread)
        pass_on();
      else
        relay.changed.notify_all();
    }
  };

  std::vector<std::thread> pool;
  for (size_t h = 0; h < helpers; ++h) {
    try {
      pool.emplace_back([&] {
        if (spare) spare->start_working();
        take_jobs(false);
        if (spare) spare->stop_working();
      });
    } catch (...) {
      break;  // could not start a thread: the others and this one take its jobs
    }
  }
  take_jobs(true);
  {
    // The helpers' reports, as they come, until every job has ended.
    const IdleWhileWaiting waiting(spare);
    while (relayed < n) {
      {
        std::unique_lock<std::mutex> lock(relay.mutex);
        relay.changed.wait(lock, [&] { return !relay.reports[relayed].empty() || relay.ended[relayed]; });
      }
      pass_on();
    }
    for (auto& t : pool) t.join();
  }

  // A job's own failure before the cancels it caused in the others.
  for (const auto& error : errors)
    if (error && !is_cancel(error)) std::rethrow_exception(error);
  if (cancelled) std::rethrow_exception(cancelled);
  for (const auto& error : errors)
    if (error) std::rethrow_exception(error);
}

BackgroundJob::BackgroundJob(Job job, SpareCores* spare) : job_(std::move(job)), spare_(spare) {
  const auto run = [this] {
    try {
      job_(Progress{&BackgroundJob::queue_report, this, 0.0, 1.0});
    } catch (...) {
      error_ = std::current_exception();
    }
  };
  try {
    if (spare_) spare_->start_working();
    thread_ = std::thread([this, run] {
      run();
      if (spare_) spare_->stop_working();
      const std::lock_guard<std::mutex> lock(mutex_);
      ended_ = true;
      changed_.notify_all();
    });
  } catch (...) {
    // No thread: the job runs now, on the calling thread, whose core counts
    // already; a caller waiting for something the job makes cannot wait for
    // ever.
    if (spare_) spare_->stop_working();
    run();
    ended_ = true;
  }
}

BackgroundJob::~BackgroundJob() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

bool BackgroundJob::queue_report(double, const char* stage, void* user) {
  auto* self = static_cast<BackgroundJob*>(user);
  {
    const std::lock_guard<std::mutex> lock(self->mutex_);
    self->stages_.push_back(stage);
  }
  self->changed_.notify_all();
  return !self->stop_.load();
}

void BackgroundJob::join(const Progress& progress, double fraction) {
  if (joined_) return;
  joined_ = true;
  {
    const IdleWhileWaiting waiting(thread_.joinable() ? spare_ : nullptr);
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
      changed_.wait(lock, [this] { return ended_ || !stages_.empty(); });
      std::deque<const char*> stages;
      stages.swap(stages_);
      const bool ended = ended_;
      lock.unlock();
      for (const char* stage : stages) progress.report(fraction, stage);
      if (ended) break;
      lock.lock();
    }
  }
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(error_);
}

void parallel_for(Eigen::Index count, Eigen::Index chunk, int threads,
                  const std::function<void(Eigen::Index, Eigen::Index)>& body) {
  if (count <= 0) return;
  chunk = std::max<Eigen::Index>(chunk, 1);
  const Eigen::Index chunks = (count + chunk - 1) / chunk;
  const unsigned cores = thread_count(threads);
  const auto workers = static_cast<size_t>(std::min<Eigen::Index>(std::min(cores, kMostLoopThreads), chunks));
  std::vector<std::exception_ptr> errors(static_cast<size_t>(chunks));
  std::atomic<Eigen::Index> next{0};
  const auto work = [&] {
    for (Eigen::Index k = next++; k < chunks; k = next++) {
      try {
        body(k * chunk, std::min(count, (k + 1) * chunk));
      } catch (...) {
        errors[static_cast<size_t>(k)] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < workers; ++t) {
    try {
      pool.emplace_back(work);
    } catch (...) {
      break;  // could not start a thread: the others and this one do the chunks
    }
  }
  work();
  for (auto& t : pool) t.join();
  for (const auto& error : errors)
    if (error) std::rethrow_exception(error);
}

void parallel_for(Eigen::Index count, Eigen::Index chunk, SpareCores* spare,
                  const std::function<void(Eigen::Index, Eigen::Index)>& body) {
  const Eigen::Index chunks = (count + std::max<Eigen::Index>(chunk, 1) - 1) / std::max<Eigen::Index>(chunk, 1);
  const CoreLease lease(chunks > 1 ? spare : nullptr,
                        static_cast<unsigned>(std::min<Eigen::Index>(chunks - 1, kMostLoopThreads - 1)));
  parallel_for(count, chunk, lease.threads(), body);
}

}  // namespace developable
