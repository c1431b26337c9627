// The job queue's workers: K threads, each taking the next queued job from the store (highest
// priority, oldest first), running it with `threads_per_job` OpenMP threads through the one runner
// into a StoreSink, which stores curve rows, snapshots and progress at least every `progress_seconds`. HTTP handler threads never run simulations:
// they only submit to the store and notify() the pool.
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "api/job_sink.h"
#include "server/executor.h"
#include "server/store/job_store.h"

namespace granulab::server {

class StoreSink;

class WorkerPool : public Executor {
 public:
  WorkerPool(JobStore& store, int workers, int threads_per_job, double progress_seconds = 1.0);
  ~WorkerPool() override;  // stop()

  /// At most this many running jobs per owner (0 = no limit); set before start().
  void set_max_running_per_owner(int n) { max_running_per_owner_ = n; }
  /// A running job stores a checkpoint this often (s; 0 = never); a job the daemon loses resumes from it.
  void set_checkpoint_seconds(double s) { checkpoint_seconds_ = s; }
  void start() override;
  /// A job was submitted: wake an idle worker.
  void notify() override;
  /// Stops taking jobs; running jobs are interrupted and left `running` in the store for the caller
  /// (granulabd re-queues them; nothing submitted is lost, their partial work is).
  void stop() override;

  int running() const { return running_.load(); }
  std::string name() const override { return "local"; }
  int workers() const override { return workers_; }
  int threads_per_job() const override { return threads_per_job_; }
  double checkpoint_seconds() const override { return checkpoint_seconds_; }

 private:
  void work();
  void run_job(const JobRecord& job);
  /// Writes a job's end to the store; a failing store is logged, never thrown out of the worker.
  void record_end(std::int64_t job, const std::function<void()>& write);
  /// A cancelled or failed run keeps the rows and snapshots it made since the last batch.
  void keep_partial_results(StoreSink& sink, std::int64_t job);

  JobStore& store_;
  int workers_, threads_per_job_;
  int max_running_per_owner_ = 0;
  double checkpoint_seconds_ = 60;
  double progress_seconds_;
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> running_{0};
};

}  // namespace granulab::server
