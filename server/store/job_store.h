// The daemon's durable state: jobs, their results (curve, snapshots) and an event log, in one SQLite
// file (or ":memory:" for tests). Every state change is one transaction, so a crash or an exception
// midway leaves each job in exactly one state. One connection serves all threads, guarded by a mutex:
// the store is never the bottleneck next to experiments that run for minutes.
//
// Job life cycle (docs/api.md, HTTP API):
//   queued ──claim_next──▶ running ──succeed──▶ succeeded
//     │                      ├──fail──────────▶ failed
//     │                      └──mark_cancelled▶ cancelled   (after request_cancel set cancel_requested)
//     └──request_cancel──────────────────────▶ cancelled
//   running ──requeue_running (daemon restart)──▶ queued
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "api/job_status.h"
#include "api/stored_row.h"

namespace granulab::server {

using api::JobStatus;

namespace sqlite {
class Database;
}

struct JobRecord {
  std::int64_t id = 0;
  JobStatus status = JobStatus::queued;
  std::string label;
  std::string experiment;
  std::string spec_json;
  std::string spec_hash;
  std::string engine_version;
  std::string owner;
  std::string error;             ///< empty unless failed
  std::string summary_json;      ///< empty unless succeeded
  int priority = 0;              ///< higher runs first
  double progress = 0.0;         ///< 0..1
  double eta_seconds = -1.0;     ///< s; negative = unknown
  std::int64_t created_ms = 0;   ///< ms since the Unix epoch
  std::int64_t started_ms = 0;   ///< ms since the Unix epoch; 0 = not started
  std::int64_t finished_ms = 0;  ///< ms since the Unix epoch; 0 = not finished
  bool cancel_requested = false;
  std::int64_t sweep_id = 0;  ///< 0 = not part of a sweep
  std::string sweep_values;   ///< JSON {"dotted.key": value} of its point in the sweep
  std::string slurm_job_id;   ///< the Slurm job running it ("123", "123_4" in an array); empty = none
  std::string slurm_state;    ///< Slurm's latest word on that job, e.g. "PENDING (Priority)"
  int slurm_attempts = 0;     ///< Slurm jobs it was given (more than one after a requeue)
};

struct SweepRecord {
  std::int64_t id = 0;
  std::string label, owner, mode;
  std::string base_json, vary_json;
  std::int64_t created_ms = 0;  ///< ms since the Unix epoch
};

struct SnapshotInfo {
  int index = 0;
  double strain = 0.0;    ///< axial strain at which the snapshot was taken (dimensionless)
  std::size_t bytes = 0;  ///< size of the stored blob
};

class JobStore {
 public:
  enum class CancelResult {
    cancelled_queued,   ///< was queued: now cancelled
    requested_running,  ///< is running: cancel_requested set, the worker stops and calls mark_cancelled
    not_found,
    wrong_state,  ///< already succeeded, failed or cancelled
  };

  /// Opens or creates the database at `path` (":memory:" allowed) and brings its schema up to date.
  /// The parent directory must exist.
  /// `max_bytes` > 0: the file may not grow past it; writes beyond fail with sqlite::StoreFull, as on a
  /// full disk (granulabd --max-db-mb).
  explicit JobStore(const std::string& path, std::int64_t max_bytes = 0);
  ~JobStore();
  JobStore(const JobStore&) = delete;
  JobStore& operator=(const JobStore&) = delete;

  /// Adds a queued job; returns its id (ids grow with submission order).
  /// `expected_bytes`: what the job is expected to store at most (results and checkpoints, B), counted
  /// against the room left while it is queued or running (space()).
  std::int64_t submit(const std::string& spec_json, const std::string& experiment, const std::string& label,
                      const std::string& spec_hash, const std::string& engine_version, const std::string& owner,
                      int priority, double expected_bytes = 0);

  /// Atomically takes the queued job with the highest priority (within a priority: fair share between
  /// owners, the one with the fewest running first, then the one whose last job started longest ago, then
  /// the oldest job), marks it running with started_ms = now and returns it as it now is; nullopt when the
  /// queue is empty.
  /// `max_running_per_owner` > 0: skips jobs whose owner already has that many running.
  std::optional<JobRecord> claim_next(int max_running_per_owner = 0);

  /// Progress of a running job (clamped to 0..1; a non-finite or negative eta stores "unknown").
  /// Ignored unless the job is running.
  void set_progress(std::int64_t id, double progress, double eta_seconds);

  /// Finishing transitions. Each returns true if it applied, false if the job does not exist or is not
  /// in a state it may leave that way: succeed needs running; fail and mark_cancelled accept queued or
  /// running. A false result changes nothing.
  bool succeed(std::int64_t id, const std::string& summary_json, const std::string& curve_csv,
               const std::string& curve_json);
  bool fail(std::int64_t id, const std::string& error);
  bool mark_cancelled(std::int64_t id);

  CancelResult request_cancel(std::int64_t id);
  enum class WriteResult { done, not_found, wrong_state };
  /// Deletes a finished job with its curve and snapshots (wrong_state while queued or running).
  WriteResult remove(std::int64_t id);
  /// Changes the priority of a queued job (wrong_state otherwise).
  WriteResult set_priority(std::int64_t id, int priority);
  /// True if a cancel was requested for this running job (false for unknown ids).
  bool cancel_requested(std::int64_t id);

  std::optional<JobRecord> get(std::int64_t id);

  /// A job of a sweep, before it exists.
  struct SweepJob {
    std::string spec_json, experiment, label, spec_hash, values_json;
    double expected_bytes = 0;  ///< as submit()'s
  };
  /// Creates the sweep and all its jobs (queued) in one transaction; returns the sweep's id and the jobs'.
  std::pair<std::int64_t, std::vector<std::int64_t>> submit_sweep(const SweepRecord& sweep,
                                                                  const std::vector<SweepJob>& jobs,
                                                                  const std::string& engine_version, int priority);
  std::optional<SweepRecord> get_sweep(std::int64_t id);
  /// Newest first; `owner_filter` empty = all.
  std::vector<SweepRecord> list_sweeps(int limit, std::int64_t offset, const std::string& owner_filter = "");
  /// The sweep's jobs, in the order of its points.
  std::vector<JobRecord> sweep_jobs(std::int64_t sweep_id);
  /// Newest first. `status_filter` nullopt / `owner_filter` empty = any; `limit` < 0 = no limit. The
  /// records have no spec_json (a listing shows none; get() has it).
  std::vector<JobRecord> list(std::optional<JobStatus> status_filter, int limit, std::int64_t offset,
                              const std::string& owner_filter = "");
  /// Jobs in `status` (nullopt = all jobs), of `owner` when not empty.
  std::size_t count(std::optional<JobStatus> status, const std::string& owner = "");

  std::optional<std::string> curve_csv(std::int64_t id);
  std::optional<std::string> curve_json(std::int64_t id);

  /// A job's results while it runs, written by its worker in batches (server/store_sink.h).
  struct SnapshotBlob {
    int index = 0;
    double strain = 0.0;  ///< axial strain when taken (-)
    std::string data;     ///< the compact JSON
  };
  /// Starts the job's live curve: its CSV header (newline included); drops rows of an earlier attempt.
  void start_curve(std::int64_t id, const std::string& header);
  /// Appends curve lines (newline included) numbered from `first_index`, and snapshots, in one
  /// transaction. Ignored unless the job is running.
  /// A running job's checkpoint: the engine's state after `rows` curve rows and `snapshots` snapshots,
  /// stored as `chunks` chunks (rows of checkpoint_chunks, each at most CheckpointWriter::kChunkBytes)
  /// of `bytes` in all, under its `generation`. A checkpoint's chunks are written one per transaction
  /// while the previous checkpoint stays the job's; append_results then switches to the new generation in
  /// one transaction with the rows and snapshots it follows. Chunks of no checkpoint (replaced, dropped,
  /// or of a write that never finished) are garbage that drop_checkpoint_garbage removes a chunk at a
  /// time, so that no transaction ever holds the store for a whole large checkpoint.
  struct Checkpoint {
    std::int64_t generation = 0, chunks = 0, bytes = 0;
    std::int64_t rows = 0, snapshots = 0;
    std::string engine_version;  ///< of the build that wrote it: another build starts the job afresh
  };
  /// A new checkpoint of a running job begins: its generation. An earlier write of the job still under
  /// way is abandoned.
  std::int64_t begin_checkpoint(std::int64_t id);
  /// Chunk `index` of generation `generation` (from begin_checkpoint), in its own short transaction;
  /// false, and nothing stored, unless that write is under way (not ended, nor replaced by a later
  /// begin_checkpoint of the job, nor begun before the daemon restarted). Throws sqlite::StoreFull when
  /// the store cannot hold it (then end_checkpoint_write and give up).
  bool put_checkpoint_chunk(std::int64_t id, std::int64_t generation, std::int64_t index, const char* data,
                            std::size_t size);
  /// The write of `generation` is over, stored by append_results or given up (its chunks are garbage).
  void end_checkpoint_write(std::int64_t id, std::int64_t generation);
  /// With `checkpoint` (its chunks all put), makes it the job's in the same transaction as the rows and
  /// snapshots it goes with; the previous checkpoint's chunks become garbage.
  void append_results(std::int64_t id, std::size_t first_index, const std::vector<api::StoredRow>& rows,
                      const std::vector<SnapshotBlob>& snapshots, const Checkpoint* checkpoint = nullptr);
  std::optional<Checkpoint> checkpoint(std::int64_t id);
  /// One chunk of a stored checkpoint; nullopt if it is gone (the checkpoint was replaced or dropped).
  std::optional<std::string> checkpoint_chunk(std::int64_t id, std::int64_t generation, std::int64_t index);
  /// Removes up to `max_chunks` chunks that belong to no checkpoint (one transaction each); how many.
  std::size_t drop_checkpoint_garbage(std::size_t max_chunks);
  /// Before a resumed run: drops the rows and snapshots made after the checkpoint (they are made again).
  void trim_results(std::int64_t id, std::int64_t rows, std::int64_t snapshots);
  /// A job that starts afresh after all (e.g. its checkpoint is of another build): drops the checkpoint
  /// and every result.
  void discard_partial_results(std::int64_t id);
  /// The curve as CSV: the stored whole curve of a succeeded job, else the header and the rows written so
  /// far (running, and what a cancelled or failed job computed); nullopt when there is none.
  std::optional<std::string> live_curve_csv(std::int64_t id);
  /// The curve's header line and its latest stored row while the job runs or after it stopped without
  /// succeeding; nullopt when no row is stored.
  std::optional<std::pair<std::string, api::StoredRow>> latest_row(std::int64_t id);
  /// The header line and every stored row of a job's live curve (running, cancelled or failed); nullopt
  /// when it has no header (never started).
  std::optional<std::pair<std::string, std::vector<api::StoredRow>>> live_rows(std::int64_t id);

  /// Stores snapshot `index` of a job as a BLOB (replacing one already stored under that index).
  void add_snapshot(std::int64_t job_id, int index, double strain, const std::vector<std::uint8_t>& blob);
  /// The job's snapshots, by index (without their data).
  std::vector<SnapshotInfo> snapshots(std::int64_t job_id);
  std::optional<std::vector<std::uint8_t>> snapshot(std::int64_t job_id, int index);

  /// The newest succeeded job with this spec hash and engine version (for ?reuse=true); an empty hash
  /// never matches.
  /// With `owner`, only that owner's jobs (a private server must not tell one user of another's specs).
  std::optional<std::int64_t> find_succeeded(const std::string& spec_hash, const std::string& engine_version,
                                             const std::optional<std::string>& owner = std::nullopt);

  /// Daemon start-up: every job left running by a previous process goes back to the queue (progress 0,
  /// started_ms 0, cancel_requested cleared, its partial curve and snapshots dropped unless a checkpoint
  /// keeps them) with a "requeued" event. Returns how many. Call before any worker starts.
  /// `keep_cluster_jobs`: jobs on a Slurm cluster are left as they are (their Slurm jobs still run them);
  /// otherwise they are taken back too.
  std::size_t requeue_running(bool keep_cluster_jobs = false);

  // Jobs on a Slurm cluster (server/slurm/slurm_executor.h); job_store_cluster.cpp.
  /// Queued jobs not yet given to the cluster, best first (priority, then age), at most `limit`.
  std::vector<JobRecord> unsubmitted(int limit);
  /// The secret the job's worker presents, set to `fresh` the first time (then kept); empty for an unknown
  /// job, or when none is set and `fresh` is empty.
  std::string worker_token(std::int64_t id, const std::string& fresh = "");
  /// The job went to Slurm as `slurm_job_id`: only while it is queued and not on the cluster yet (false
  /// otherwise, e.g. cancelled meanwhile).
  bool set_slurm_job(std::int64_t id, const std::string& slurm_job_id);
  /// Jobs whose Slurm job has not been seen to end, whatever their status (a cancelled one may still need
  /// its Slurm job cancelled).
  std::vector<JobRecord> on_cluster();
  /// Slurm's latest word on the job's Slurm job `slurm_job_id`; `ended`: that Slurm job is over. Ignored
  /// when the job has moved to another Slurm job since (a requeue).
  void set_slurm_state(std::int64_t id, const std::string& slurm_job_id, const std::string& state, bool ended);
  /// Its worker started: queued -> running (started_ms now), only while it is on `slurm_job_id` (empty: any,
  /// for a worker outside Slurm). True if it is running now.
  bool mark_running(std::int64_t id, const std::string& slurm_job_id = "");
  /// What happens after its Slurm job stopped short (a time limit, a lost node, a worker interrupted).
  enum class Requeue { requeued, cancelled, failed, not_active };
  /// Back in the queue for another Slurm job, its checkpoint and the results up to it kept; or cancelled
  /// when a cancel was requested meanwhile; or failed when it had `max_attempts` Slurm jobs already (the
  /// message names the limit). not_active unless queued or running.
  Requeue requeue_for_cluster(std::int64_t id, const std::string& reason, int max_attempts = kMaxSlurmAttempts);
  static constexpr int kMaxSlurmAttempts = 10;  ///< Slurm jobs one job may be given (requeues included)
  /// (job id, worker secret) of every queued or running job that has one.
  std::vector<std::pair<std::int64_t, std::string>> worker_secrets();

  /// Appends to the event log; job_id 0 = an event about the daemon, not one job (an unknown job id
  /// throws: the foreign key).
  void log_event(std::int64_t job_id, const std::string& kind, const std::string& message);
  /// The job's events, oldest first, each as "kind: message" (job_id 0 = the daemon's events).
  std::vector<std::string> events(std::int64_t job_id);

  /// The store's room (B), counted before work is accepted (docs/api.md, "What survives what").
  struct Space {
    double used = 0;       ///< the file's pages in use and its write-ahead log (B)
    double room = 0;       ///< what may still be written: to --max-db-mb (the log counted) or the disk's free space
    double committed = 0;  ///< the expected_bytes of the jobs queued or running (B)
    bool limited = false;  ///< false for an in-memory store (no limit known)
  };
  Space space();
  /// What `owner`'s jobs hold or may still write (B): the expected_bytes of those queued or running, and what
  /// each finished one stores (its spec, curve, rows and snapshots, counted when it finished). The per-user
  /// quota of --max-user-mb (docs/api.md, "Budgets").
  double user_bytes(const std::string& owner);
  /// A file of a few MB beside the database, made at open when the disk has room: deleted when the store is
  /// full, so that the failure of a job (and a cancel) can still be written. True when there was one.
  bool release_reserve();

 private:
  /// Makes the reserve file at open when there is none and the disk has room (the constructor only).
  void make_reserve();
  /// A job's status, or nullopt for an unknown id (the caller holds the lock).
  std::optional<JobStatus> status_locked(std::int64_t id);
  /// A live curve's header and its rows (or only its latest); nullopt without a header.
  std::optional<std::pair<std::string, std::vector<api::StoredRow>>> live_rows_locked(std::int64_t id, bool last_only);
  /// The one finishing move (the caller holds the lock, in a transaction): `to` (succeeded, failed or
  /// cancelled) from one of `from`, finished now, with its event; a finished job keeps no checkpoint.
  /// False, and nothing changed, when the job is unknown or not in `from`.
  bool finish_locked(std::int64_t id, JobStatus to, std::initializer_list<JobStatus> from, const std::string& event);
  void drop_checkpoint_locked(std::int64_t id);
  /// A finished job's expected_bytes becomes what it stores (its checkpoint is gone): user_bytes counts that.
  void settle_stored_bytes_locked(std::int64_t id);
  void log_event_locked(std::int64_t job_id, const std::string& kind, const std::string& message);
  std::optional<JobRecord> get_locked(std::int64_t id);
  std::optional<std::string> curve_column(std::int64_t id, const char* column);

  std::mutex mutex_;
  std::unique_ptr<sqlite::Database> db_;
  std::set<std::pair<std::int64_t, std::int64_t>> checkpoint_writes_;  ///< (job, generation) being written
  std::int64_t max_bytes_ = 0;
  std::string reserve_path_;  ///< empty: none (in memory, or no room for it at open)
};

}  // namespace granulab::server
