// Independent jobs on the cores, with the caller's progress and cancel.
//
// Least motion's candidates (pipeline.cpp) are polishes that share nothing
// but read-only inputs; run one after the other they took half of a
// 10k-50k-face run. run_concurrently runs such jobs on up to `threads`
// threads, the calling thread among them.
//
// Only the calling thread calls the caller's progress callback (the add-on's
// is Python and Blender's), in job order: the reports of job 0, then of job
// 1, and so on, whatever the thread count, so the fraction never goes back.
// Every job queues its reports and hears only "stop?" back; the calling
// thread passes the queues on, as far as the job order allows, at each
// report of its own job and once it has no job left. When the callback cancels, every
// job stops at its next report, the rest of the reports are dropped, all are
// joined and EngineError(cancelled) is rethrown.
//
// Each job must give the same result whichever thread runs it (no shared
// mutable state): the results then do not depend on the thread count.
#pragma once

#include "core/types.h"

#include <Eigen/Core>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace developable {

using Job = std::function<void(const Progress&)>;

// The most threads parallel_for runs a loop on, the calling one included.
inline constexpr unsigned kMostLoopThreads = 8;

// The cores of a run that none of its threads is working on. Work that can
// share out over more cores (a polish's products) takes one only while it
// would idle: least motion's candidates run one to a core, and once the
// short ones end, the long one left takes the freed cores (docs/method.md,
// "Spare cores"). run_concurrently counts its threads in and out; the
// thread that makes a SpareCores counts as working. The count may go below
// zero (more threads than cores): nothing is then taken.
class SpareCores {
 public:
  // thread_count(threads) cores, one of them the calling thread's.
  explicit SpareCores(int threads);
  SpareCores(const SpareCores&) = delete;
  SpareCores& operator=(const SpareCores&) = delete;

  // Takes up to `most` spare cores; returns how many it took (0 when none
  // is spare). Give them back with give_back.
  unsigned take(unsigned most);
  void give_back(unsigned count);

  // A thread starts or stops working (run_concurrently's threads).
  void start_working() { --spare_; }
  void stop_working() { ++spare_; }

 private:
  std::atomic<int> spare_;
};

// Runs every job once and returns when all are done.
//   jobs: independent tasks; job k reports through the Progress it is given
//   (its reports reach the callback in progress.sub(k / n, (k + 1) / n)).
//   Each thread, the calling one among them, takes the next job not yet
//   taken until none is left (a thread that cannot be started leaves its
//   share to the others); put the long jobs first.
//   threads: at most this many threads, the calling one included; 0: one
//   per core.
//   progress: the caller's callback, called from the calling thread only
//   (at its own jobs' reports and between its jobs, and while it waits for
//   the others once none is left).
//   spare: null, or the run's spare cores: each thread counts as working
//   while it runs jobs, the calling thread not while it waits for the others.
void run_concurrently(const std::vector<Job>& jobs, int threads, const Progress& progress, SpareCores* spare = nullptr);

// One job on a thread of its own, started now and joined when the caller
// needs its result: work that depends on the input alone (least motion's
// polishes of its starts) runs beside the stages before the ones that need
// it. Its reports are queued and reach the caller's callback at the join,
// from the calling thread, one for one (so a run reports as often whatever
// ran where); it hears only "stop?", which is "yes" once the BackgroundJob
// is destroyed (a cancel unwinding the caller), so it stops at its next
// report. Where no thread can be started, the job runs at once in the
// constructor, on the calling thread. The thread counts as working in
// `spare` while it runs.
class BackgroundJob {
 public:
  BackgroundJob(Job job, SpareCores* spare);
  ~BackgroundJob();
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;

  // Waits for the job to end, passing its reports on to `progress` (each at
  // `fraction`, under its own stage) as they come, so a cancel is heard at
  // the job's next report; the calling thread's core is spare meanwhile.
  // Rethrows what the job threw. Once only.
  void join(const Progress& progress, double fraction);

 private:
  static bool queue_report(double fraction, const char* stage, void* user);

  Job job_;
  SpareCores* spare_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<const char*> stages_;  // reports not yet passed on, under mutex_
  bool ended_ = false;              // under mutex_
  std::exception_ptr error_;
  std::thread thread_;
  bool joined_ = false;
};

// The threads that `threads` asks for: itself when positive, else one per
// core (at least 1).
unsigned thread_count(int threads);

// Runs body(begin, end) once for each chunk [k chunk, (k + 1) chunk) of
// [0, count), the chunks taken in turn by up to `threads` threads (the
// calling one included; 0: one per core, at most kMostLoopThreads). The chunks are fixed
// whatever the thread count, so a body that writes only its own items gives
// the same result on any number of threads. Loops over a mesh's faces in
// the iterations use it (the target search, a step's right-hand side); a
// loop of one chunk runs on the calling thread alone, so small meshes start
// no thread. No progress: a body is short.
// Every chunk runs, even after one threw; then the exception of the lowest
// chunk that threw is rethrown (the same whatever the thread count).
void parallel_for(Eigen::Index count, Eigen::Index chunk, int threads,
                  const std::function<void(Eigen::Index, Eigen::Index)>& body);

// Up to `most` of the spare cores (none when `spare` is null), held while
// the lease lives.
class CoreLease {
 public:
  CoreLease(SpareCores* spare, unsigned most) : spare_(spare), taken_(spare != nullptr ? spare->take(most) : 0) {}
  ~CoreLease() {
    if (taken_ > 0) spare_->give_back(taken_);
  }
  CoreLease(const CoreLease&) = delete;
  CoreLease& operator=(const CoreLease&) = delete;

  // The calling thread and the cores taken.
  int threads() const { return static_cast<int>(taken_) + 1; }

 private:
  SpareCores* spare_;
  unsigned taken_;
};

// parallel_for on the calling thread and the cores `spare` has spare (as
// many as the chunks can use, at most kMostLoopThreads threads, given back at the end); on
// the calling thread alone when `spare` is null or has none. The same result
// whatever it takes.
void parallel_for(Eigen::Index count, Eigen::Index chunk, SpareCores* spare,
                  const std::function<void(Eigen::Index, Eigen::Index)>& body);

}  // namespace developable
