// `granulabd --executor slurm`: every job becomes a Slurm batch job (a sweep's jobs queued together become
// one job array) that runs `granulab worker` on the node Slurm picks. The worker fetches its spec from the
// daemon and sends its results back over HTTP (server/worker_routes.cpp): the cluster needs no shared
// filesystem, only the granulab binary at the same path and a route to --public-url.
//
// One thread follows the cluster, every `poll_seconds` and whenever notified:
// - queued jobs not yet on the cluster are submitted, with the job's secret in the Slurm job's
//   environment, its threads as cpus_per_task, a time limit from its workload estimate and a USR1
//   warning `signal_seconds` before it (the worker then checkpoints and the job is requeued);
// - the state of every job still on the cluster is read from slurmrestd: PENDING stays `queued` and
//   RUNNING becomes `running`, with Slurm's state and reason in `slurm_state`; a Slurm job that ended
//   without its worker reporting (FAILED, TIMEOUT, NODE_FAIL, OUT_OF_MEMORY, CANCELLED, ...) fails or
//   cancels the job with the reason, or requeues it from its checkpoint after a time limit or a lost node;
// - a cancel requested through the API cancels the Slurm job.
// Slurm forgets finished jobs (no accounting database is assumed), so the store keeps every state the
// daemon needs; after a restart the thread simply follows the jobs the store says are on the cluster.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "server/executor.h"
#include "server/slurm/slurm_rest.h"
#include "server/store/job_store.h"

namespace granulab::server::slurm {

struct ExecutorOptions {
  RestOptions rest;
  std::string partition;             ///< empty: the cluster's default
  std::string public_url;            ///< where workers reach this daemon, e.g. http://10.0.0.5:8080
  std::string worker_binary;         ///< the granulab binary on the nodes (default: next to granulabd)
  std::string worker_ca_file;        ///< the CA a worker trusts for an https public_url, as the nodes see it (or none)
  std::string output = "/dev/null";  ///< the Slurm jobs' standard output and error (Slurm's patterns, e.g. %j)
  int threads_per_job = 1;           ///< cpus_per_task of a job whose spec leaves run.threads at 0
  double checkpoint_seconds = 60;
  int max_time_limit_minutes = 7 * 24 * 60;
  int signal_seconds = 120;  ///< USR1 this long before the time limit
  double poll_seconds = 2;
};

class SlurmExecutor : public Executor {
 public:
  /// Checks slurmrestd's dialect and the worker binary (throws std::runtime_error naming the problem).
  SlurmExecutor(JobStore& store, ExecutorOptions options);
  ~SlurmExecutor() override;
  void start() override;
  void stop() override;
  void notify() override;
  void cancel_requested(std::int64_t job) override;
  std::string name() const override { return "slurm"; }
  int workers() const override { return 0; }
  int threads_per_job() const override { return options_.threads_per_job; }
  double checkpoint_seconds() const override { return options_.checkpoint_seconds; }
  const std::string& cluster() const { return cluster_; }  ///< "Slurm 22.05.8 (openapi/v0.0.38)"
  /// Where workers reach the daemon; set before start().
  void set_public_url(std::string url) { options_.public_url = std::move(url); }
  const std::string& public_url() const { return options_.public_url; }

  /// The Slurm time limit of a job (minutes): 3x its expected run time at a conservative 5e7 sphere-steps
  /// per second per thread, plus 5 minutes, at most max_time_limit_minutes. Public for tests.
  int time_limit_minutes(const server::JobRecord& job, int threads) const;

 private:
  void work();
  /// Queued jobs not on the cluster yet go to Slurm (a sweep's neighbours as one array).
  void submit_queued();
  /// Reads the state of every job still on the cluster and acts on it.
  void follow();
  /// Acts on one job's Slurm record (null: Slurm does not know its job any more).
  void follow_one(const server::JobRecord& listed, const SlurmJob* record);

  JobStore& store_;
  ExecutorOptions options_;
  RestClient rest_;
  std::string cluster_;
  std::set<std::string> cancels_sent_;  // Slurm ids already cancelled (the worker thread only)
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool woken_ = false;
  std::atomic<bool> stopping_{false};
};

}  // namespace granulab::server::slurm
