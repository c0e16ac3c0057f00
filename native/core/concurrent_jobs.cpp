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

// What the threads share: each job's reports not yet passed on, which jobs
// have ended, and the stop every job hears at its next report.
struct Relay {
  explicit Relay(size_t jobs) : reports(jobs), ended(jobs, false) {}

  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::deque<Report>> reports;
  std::vector<bool> ended;
  std::atomic<bool> stop{false};
};

// The progress callback of a job on another thread: its report is queued
// for the calling thread, and the answer is only "stop?".
struct QueuedProgress {
  Relay* relay;
  size_t job;

  static bool call(double fraction, const char* stage, void* user) {
    const auto* self = static_cast<const QueuedProgress*>(user);
    {
      const std::lock_guard<std::mutex> lock(self->relay->mutex);
      self->relay->reports[self->job].push_back({fraction, stage});
    }
    self->relay->changed.notify_all();
    return !self->relay->stop.load();
  }
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

void run_concurrently(const std::vector<Job>& jobs, int threads, const Progress& progress) {
  const size_t n = jobs.size();
  if (n == 0) return;
  const size_t cores = thread_count(threads);
  const size_t helpers = std::min(cores, n) - 1;  // threads besides the calling one

  Relay relay(n);
  std::vector<std::exception_ptr> errors(n);
  std::vector<QueuedProgress> queued(n);
  for (size_t k = 0; k < n; ++k) queued[k] = {&relay, k};
  const double share = 1.0 / static_cast<double>(n);
  const auto own_share = [&](size_t k) {
    return progress.sub(share * static_cast<double>(k), share * static_cast<double>(k + 1));
  };
  const auto run_job = [&](size_t k, const Progress& job_progress) {
    if (!relay.stop) {
      try {
        jobs[k](job_progress);
      } catch (...) {
        errors[k] = std::current_exception();
        relay.stop = true;
      }
    }
    {
      const std::lock_guard<std::mutex> lock(relay.mutex);
      relay.ended[k] = true;
    }
    relay.changed.notify_all();
  };

  // Jobs 1, 2, ... go to the helpers in turn (a fixed assignment); job 0,
  // and the jobs of a helper that could not be started, to this thread.
  std::vector<std::thread> pool;
  for (size_t h = 0; h < helpers; ++h) {
    try {
      pool.emplace_back([&, h] {
        for (size_t k = 1 + h; k < n; k += helpers) run_job(k, Progress{&QueuedProgress::call, &queued[k], 0.0, 1.0});
      });
    } catch (...) {
      break;  // could not start a thread: this one does its jobs
    }
  }
  const size_t started = pool.size();
  const auto on_helper = [&](size_t k) { return k > 0 && (k - 1) % std::max<size_t>(helpers, 1) < started; };

  // This thread's jobs report straight to the callback; the helpers' reports
  // are passed on after them, job by job, as they come. A cancel stops every
  // job at its next report and the rest of the reports are dropped.
  std::exception_ptr cancelled;
  for (size_t k = 0; k < n; ++k) {
    if (!on_helper(k)) {
      run_job(k, own_share(k));
      continue;
    }
    for (;;) {
      std::deque<Report> batch;
      bool ended = false;
      {
        std::unique_lock<std::mutex> lock(relay.mutex);
        relay.changed.wait(lock, [&] { return !relay.reports[k].empty() || relay.ended[k]; });
        batch.swap(relay.reports[k]);
        ended = relay.ended[k];
      }
      for (const Report& r : batch) {
        if (cancelled || relay.stop) break;
        try {
          own_share(k).report(r.fraction, r.stage);
        } catch (...) {
          cancelled = std::current_exception();
          relay.stop = true;
        }
      }
      if (ended) break;
    }
  }
  for (auto& t : pool) t.join();

  // A job's own failure before the cancels it caused in the others.
  for (const auto& error : errors)
    if (error && !is_cancel(error)) std::rethrow_exception(error);
  if (cancelled) std::rethrow_exception(cancelled);
  for (const auto& error : errors)
    if (error) std::rethrow_exception(error);
}

void parallel_for(Eigen::Index count, Eigen::Index chunk, int threads,
                  const std::function<void(Eigen::Index, Eigen::Index)>& body) {
  if (count <= 0) return;
  chunk = std::max<Eigen::Index>(chunk, 1);
  const Eigen::Index chunks = (count + chunk - 1) / chunk;
  const unsigned cores = thread_count(threads);
  const auto workers = static_cast<size_t>(std::min<Eigen::Index>(std::min(cores, 8u), chunks));
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

}  // namespace developable
