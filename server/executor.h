// Where the daemon's jobs run: its own pool of threads (WorkerPool, `--executor local`) or a Slurm
// cluster (SlurmExecutor, `--executor slurm`). Both take queued jobs from the store and leave every result
// there; the HTTP routes only tell them that something changed.
#pragma once

#include <cstdint>
#include <string>

namespace granulab::server {

class Executor {
 public:
  virtual ~Executor() = default;
  virtual void start() = 0;
  /// Stops taking jobs. Local: running jobs are interrupted and left `running` for the next start.
  /// Slurm: jobs on the cluster keep running there; the next start follows them again.
  virtual void stop() = 0;
  /// A job was submitted (or requeued): look at the queue now.
  virtual void notify() = 0;
  /// A cancel was requested for this job (queued or running).
  virtual void cancel_requested(std::int64_t job) { (void)job; }
  virtual std::string name() const = 0;  ///< "local" or "slurm"
  virtual int workers() const = 0;       ///< jobs that may run at once (Slurm: 0, the cluster decides)
  virtual int threads_per_job() const = 0;
  /// How often a running job stores a checkpoint (s; 0 = never).
  virtual double checkpoint_seconds() const = 0;
};

}  // namespace granulab::server
