// The server's JobSink: a running job's curve rows and snapshots go into the store in batches, at most
// every `flush_seconds` (and at the end), so GET /v1/jobs/{id}/curve serves the rows computed so far, a
// job that is cancelled or fails keeps what it computed, and one that loses its daemon keeps what it
// computed up to its last checkpoint (below) and resumes from there. Between
// batches the sink only buffers: the engine's loop never waits on SQLite for more than one batch a
// second. Progress and the cancel flag are exchanged with the store at the same rhythm; `stopping`
// (the daemon's shutdown) is checked at every progress call. Every `checkpoint_seconds` the experiment's
// state is stored too, in the same transaction as the rows and snapshots it goes with, so a job the
// daemon loses resumes from there (WorkerPool::run_job) instead of from the start.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "api/job_sink.h"
#include "api/stored_row.h"
#include "server/store/job_store.h"

namespace granulab::server {

/// Thrown when the daemon shuts down under a running job (it is re-queued, not failed).
struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted by shutdown") {}
};

class StoreSink : public api::JobSink {
 public:
  StoreSink(JobStore& store, std::int64_t job, const std::atomic<bool>& stopping, double flush_seconds,
            double checkpoint_seconds = 60, std::string engine_version = "");

  /// With `resume`: the store already holds the rows and snapshots up to the checkpoint (trimmed).
  void begin(const std::vector<CurveColumn>& columns, const api::Resume* resume) override;
  void curve_row(const std::vector<double>& values) override;
  void snapshot(std::size_t index, const GrainSnapshot& s) override;
  /// On shutdown: lets the run reach its next safe point (a checkpoint is due there), then throws
  /// Interrupted, within half a second either way. Otherwise flushes, stores progress and an ETA and returns false on a
  /// cancel request, at most every flush_seconds.
  bool progress(double fraction) override;
  bool checkpoint_due() override;
  /// Streams the state into the store in chunks, then stores it with what is buffered in one transaction.
  void checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) override;
  std::size_t checkpoints() const { return checkpoints_; }
  /// Flushes what is buffered and marks the job succeeded with its summary and whole curve.
  void summary(const nlohmann::json& summary) override;
  /// Writes what is buffered (also called by the worker when a run ends without a summary).
  void flush();

  double flush_seconds_total() const { return flush_seconds_total_; }  ///< time spent writing (s)
  std::size_t flushes() const { return flushes_; }

 private:
  JobStore& store_;
  std::int64_t job_;
  const std::atomic<bool>& stopping_;
  double flush_seconds_, checkpoint_seconds_;
  std::string engine_version_;
  std::size_t checkpoints_ = 0;
  std::chrono::steady_clock::time_point last_checkpoint_;
  std::optional<std::chrono::steady_clock::time_point> stop_seen_;  ///< when progress first saw the shutdown
  std::vector<CurveColumn> columns_;
  std::string curve_csv_;                   // the whole curve, for the final store
  std::vector<api::StoredRow> rows_;        // every row (values and line), for the final JSON curve
  std::vector<api::StoredRow> pending_rows_;  // not yet in the store
  std::size_t rows_stored_ = 0;
  std::vector<JobStore::SnapshotBlob> pending_snapshots_;
  std::chrono::steady_clock::time_point start_, last_flush_;
  double flush_seconds_total_ = 0;
  std::size_t flushes_ = 0;
};

}  // namespace granulab::server
