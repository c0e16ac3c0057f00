// concurrent_jobs.h: every job runs once, the callback only on the calling
// thread and in job order, cancels stop the others, a job's own failure
// comes first; a background job runs beside the caller and stops when
// dropped; parallel_for covers its range once in fixed chunks.
#include "core/concurrent_jobs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace developable {
namespace {

// A progress callback that records who called it with what, and cancels
// after `cancel_after` calls (never when negative).
struct Recorder {
  std::mutex mutex;
  std::vector<std::thread::id> callers;
  std::vector<double> fractions;
  std::vector<std::string> stages;
  int cancel_after = -1;

  static bool call(double fraction, const char* stage, void* user) {
    auto* self = static_cast<Recorder*>(user);
    const std::lock_guard<std::mutex> lock(self->mutex);
    self->callers.push_back(std::this_thread::get_id());
    self->fractions.push_back(fraction);
    self->stages.emplace_back(stage);
    return self->cancel_after < 0 || static_cast<int>(self->callers.size()) <= self->cancel_after;
  }
  Progress progress() { return {&Recorder::call, this, 0.0, 1.0}; }
};

// A job that reports `steps` times, a millisecond apart, under `stage`.
Job reporting_job(int steps, const char* stage, std::atomic<int>* runs) {
  return [steps, stage, runs](const Progress& progress) {
    ++*runs;
    for (int i = 0; i < steps; ++i) {
      progress.report(static_cast<double>(i) / steps, stage);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
}

// A job that reports every millisecond until told to stop; `started` is set
// when it runs, `stopped` when a cancel ended it.
Job endless_job(std::atomic<bool>* started, std::atomic<bool>* stopped) {
  return [started, stopped](const Progress& progress) {
    *started = true;
    try {
      for (;;) {
        progress.report(0.5, "endless");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    } catch (const EngineError& e) {
      *stopped = e.status() == Status::cancelled;
      throw;
    }
  };
}

TEST(ConcurrentJobs, EveryJobRunsOnceWhateverTheThreadCount) {
  for (int threads : {0, 1, 2, 3, 8}) {
    std::vector<int> result(7, 0);
    std::vector<Job> jobs;
    for (size_t k = 0; k < result.size(); ++k)
      jobs.push_back([&result, k](const Progress&) { result[k] += static_cast<int>(k * k); });
    run_concurrently(jobs, threads, Progress{});
    for (size_t k = 0; k < result.size(); ++k) EXPECT_EQ(result[k], static_cast<int>(k * k)) << threads;
  }
  run_concurrently({}, 2, Progress{});
}

// A thread takes the next job once it is free: a job that waits for a later
// one does not hold it up (a fixed assignment of jobs 1 and 2 to one helper
// would wait here for good).
TEST(ConcurrentJobs, AFreeThreadTakesTheNextJob) {
  std::mutex mutex;
  std::condition_variable changed;
  bool later_started = false;
  bool waited = false;
  const Job waits_for_later = [&](const Progress&) {
    std::unique_lock<std::mutex> lock(mutex);
    waited = changed.wait_for(lock, std::chrono::seconds(20), [&] { return later_started; });
  };
  const Job later = [&](const Progress&) {
    const std::lock_guard<std::mutex> lock(mutex);
    later_started = true;
    changed.notify_all();
  };
  run_concurrently({[](const Progress&) {}, waits_for_later, later}, 2, Progress{});
  EXPECT_TRUE(waited);
}

TEST(ConcurrentJobs, TheCallbackHearsEveryJobInOrderFromTheCallingThreadOnly) {
  std::vector<std::string> first_stages;
  for (int threads : {1, 2, 3}) {
    Recorder recorder;
    std::atomic<int> runs{0};
    // The long job last: its reports come while the short ones have ended.
    run_concurrently({reporting_job(10, "a", &runs), reporting_job(5, "b", &runs), reporting_job(30, "c", &runs)},
                     threads, recorder.progress());
    EXPECT_EQ(runs, 3);
    for (const auto& id : recorder.callers) EXPECT_EQ(id, std::this_thread::get_id());
    for (size_t i = 1; i < recorder.fractions.size(); ++i)
      EXPECT_GE(recorder.fractions[i], recorder.fractions[i - 1]) << threads;
    if (first_stages.empty()) first_stages = recorder.stages;
    EXPECT_EQ(recorder.stages, first_stages) << threads;  // job a's reports, then b's, then c's
  }
  ASSERT_EQ(first_stages.size(), 45u);
  EXPECT_EQ(first_stages.front(), "a");
  EXPECT_EQ(first_stages[10], "b");
  EXPECT_EQ(first_stages.back(), "c");
}

TEST(ConcurrentJobs, ACancelStopsEveryJobAndNothingIsReportedAfterIt) {
  for (int cancel_after : {3, 15}) {  // in the calling thread's job; in a passed-on one
    Recorder recorder;
    recorder.cancel_after = cancel_after;
    std::atomic<int> runs{0};
    std::atomic<bool> other_started{false}, other_stopped{false};
    // The other job only stops when told to (it may not start at all when the
    // cancel comes first; the call would never return if it were not told).
    const Job endless = endless_job(&other_started, &other_stopped);
    try {
      run_concurrently({reporting_job(10, "own", &runs), endless}, 2, recorder.progress());
      FAIL() << "not cancelled";
    } catch (const EngineError& e) {
      EXPECT_EQ(e.status(), Status::cancelled);
    }
    EXPECT_EQ(recorder.callers.size(), static_cast<size_t>(cancel_after + 1));
    EXPECT_TRUE(!other_started || other_stopped);
  }
}

TEST(ConcurrentJobs, AJobsOwnFailureComesBeforeTheCancelsItCaused) {
  std::atomic<int> runs{0};
  const Job failing = [](const Progress&) { throw std::runtime_error("out of luck"); };
  for (int threads : {1, 2, 3}) {
    try {
      run_concurrently({reporting_job(50, "a", &runs), failing, reporting_job(50, "c", &runs)}, threads, Progress{});
      FAIL() << "nothing thrown";
    } catch (const EngineError& e) {
      FAIL() << "a cancel came first: " << e.what();
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "out of luck");
    }
  }
}

// BackgroundJob: the job runs beside the caller, and its reports reach the
// callback at the join, from the calling thread, one for one; what the job
// threw comes back at join; join hears the caller's cancel at the job's
// next report; destroyed unjoined, the job stops at its next report.
TEST(BackgroundJob, RunsBesideTheCallerAndJoinPassesOnItsReportsAndFailure) {
  std::atomic<bool> caller_went_on{false};
  std::atomic<bool> seen_beside{false};
  std::atomic<int> reports{0};
  std::thread::id job_thread;
  SpareCores spare(2);
  {
    BackgroundJob job(
        [&](const Progress& progress) {
          job_thread = std::this_thread::get_id();
          const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
          while (!caller_went_on && std::chrono::steady_clock::now() < deadline) {
            progress.report(0.5, "beside");
            ++reports;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
          }
          seen_beside = caller_went_on.load();
          throw std::runtime_error("out of luck");
        },
        &spare);
    EXPECT_EQ(spare.take(1), 0u) << "the job's thread counts as working";
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    caller_went_on = true;
    Recorder recorder;
    try {
      job.join(recorder.progress(), 0.75);
      FAIL() << "nothing rethrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "out of luck");
    }
    EXPECT_EQ(static_cast<int>(recorder.callers.size()), reports.load()) << "every report passed on once";
    for (const std::thread::id& caller : recorder.callers) EXPECT_EQ(caller, std::this_thread::get_id());
    for (const std::string& stage : recorder.stages) EXPECT_EQ(stage, "beside");
    for (double fraction : recorder.fractions) EXPECT_EQ(fraction, 0.75);
  }
  EXPECT_TRUE(seen_beside);
  EXPECT_NE(job_thread, std::this_thread::get_id());
  EXPECT_EQ(spare.take(1), 1u) << "its core is spare again";
}

TEST(BackgroundJob, TheCallersCoreIsSpareWhileItWaits) {
  SpareCores spare(2);
  std::atomic<bool> waiting{false};
  unsigned taken = 0;
  BackgroundJob job(
      [&](const Progress&) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!waiting) std::this_thread::yield();
        while (taken == 0 && std::chrono::steady_clock::now() < deadline) {
          taken = spare.take(1);
          std::this_thread::yield();
        }
        spare.give_back(taken);
      },
      &spare);
  EXPECT_EQ(spare.take(1), 0u) << "both cores work";
  waiting = true;
  job.join(Progress{}, 0.0);
  EXPECT_EQ(taken, 1u) << "the job took the waiting caller's core";
  EXPECT_EQ(spare.take(2), 1u) << "after the join, the calling thread's core only is busy";
}

TEST(BackgroundJob, JoinHearsACancelAndTheJobStopsWhenDestroyed) {
  std::atomic<bool> started{false}, stopped{false};
  const Job endless = endless_job(&started, &stopped);
  Recorder recorder;
  recorder.cancel_after = 2;
  try {
    BackgroundJob job(endless, nullptr);
    job.join(recorder.progress(), 0.5);
    FAIL() << "not cancelled";
  } catch (const EngineError& e) {
    EXPECT_EQ(e.status(), Status::cancelled);
  }
  EXPECT_TRUE(stopped);
  stopped = false;
  { const BackgroundJob unjoined(endless, nullptr); }
  EXPECT_TRUE(stopped) << "destroyed unjoined, it stopped at its next report";
}

// Every item once, in the same chunks whatever the thread count; a loop of
// one chunk stays on the calling thread.
TEST(SpareCores, TheCoresBesidesTheCallingThreadsAreSpare) {
  SpareCores three(3);
  EXPECT_EQ(three.take(5), 2u);
  EXPECT_EQ(three.take(1), 0u);
  three.give_back(2);
  EXPECT_EQ(three.take(1), 1u);
  SpareCores one(1);
  EXPECT_EQ(one.take(1), 0u);
  one.start_working();  // a thread more than cores: still none
  one.stop_working();
  EXPECT_EQ(one.take(1), 0u);
}

// The long job finds the core of the thread whose job has ended spare,
// whichever thread ran which; after the run every core but the calling
// thread's is spare again.
TEST(SpareCores, AThreadWithNoJobLeftLeavesItsCoreSpare) {
  SpareCores spare(2);
  std::atomic<bool> short_done{false};
  std::atomic<unsigned> taken_while_both_work{0};
  std::atomic<unsigned> taken{0};
  const Job long_job = [&](const Progress&) {
    while (!short_done) std::this_thread::yield();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (taken == 0 && std::chrono::steady_clock::now() < deadline) {
      taken = spare.take(1);
      std::this_thread::yield();
    }
    spare.give_back(taken);
  };
  const Job short_job = [&](const Progress&) {
    taken_while_both_work = spare.take(1);
    spare.give_back(taken_while_both_work);
    short_done = true;
  };
  run_concurrently({long_job, short_job}, 2, Progress{}, &spare);
  EXPECT_EQ(taken_while_both_work, 0u);
  EXPECT_EQ(taken, 1u);
  EXPECT_EQ(spare.take(2), 1u) << "after the run, the calling thread's core only is busy";
}

TEST(ParallelFor, OnSpareCoresEveryItemOnceAndTheCoresGivenBack) {
  for (int threads : {1, 2, 4}) {
    SpareCores spare(threads);
    std::vector<int> hits(1000, 0);
    parallel_for(1000, 64, &spare, [&](Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index i = begin; i < end; ++i) ++hits[static_cast<size_t>(i)];
    });
    for (int h : hits) EXPECT_EQ(h, 1);
    EXPECT_EQ(spare.take(8), static_cast<unsigned>(threads - 1));
  }
}

TEST(ParallelFor, EveryItemOnceInTheSameChunks) {
  for (int threads : {0, 1, 2, 3, 8}) {
    std::vector<int> visits(1000, 0);
    std::mutex mutex;
    std::vector<std::pair<Eigen::Index, Eigen::Index>> chunks;
    parallel_for(1000, 64, threads, [&](Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index i = begin; i < end; ++i) ++visits[static_cast<size_t>(i)];
      const std::lock_guard<std::mutex> lock(mutex);
      chunks.emplace_back(begin, end);
    });
    EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), 1000) << threads;
    std::sort(chunks.begin(), chunks.end());
    ASSERT_EQ(chunks.size(), 16u) << threads;
    for (size_t k = 0; k < chunks.size(); ++k) {
      EXPECT_EQ(chunks[k].first, static_cast<Eigen::Index>(64 * k));
      EXPECT_EQ(chunks[k].second, std::min<Eigen::Index>(1000, static_cast<Eigen::Index>(64 * (k + 1))));
    }
  }
  const std::thread::id caller = std::this_thread::get_id();
  std::thread::id ran_on;
  parallel_for(10, 64, 4, [&](Eigen::Index, Eigen::Index) { ran_on = std::this_thread::get_id(); });
  EXPECT_EQ(ran_on, caller);
  parallel_for(0, 64, 2, [](Eigen::Index, Eigen::Index) { FAIL() << "an empty range ran"; });
}

TEST(ParallelFor, TheLowestFailingChunksErrorIsRethrown) {
  for (int threads : {1, 2, 3}) {
    try {
      parallel_for(100, 10, threads, [](Eigen::Index begin, Eigen::Index) {
        if (begin >= 30) throw std::runtime_error("chunk " + std::to_string(begin / 10));
      });
      FAIL() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "chunk 3") << threads;
    }
  }
}

}  // namespace
}  // namespace developable
