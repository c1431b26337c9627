#include "server/store_sink.h"

#include <algorithm>

#include "api/curve_format.h"
#include "engine/core/checkpoint.h"
#include "api/snapshot_files.h"

namespace granulab::server {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

StoreSink::StoreSink(JobStore& store, std::int64_t job, const std::atomic<bool>& stopping, double flush_seconds,
                     double checkpoint_seconds, std::string engine_version)
    : store_(store),
      job_(job),
      stopping_(stopping),
      flush_seconds_(flush_seconds),
      checkpoint_seconds_(checkpoint_seconds),
      engine_version_(std::move(engine_version)),
      last_checkpoint_(std::chrono::steady_clock::now()),
      start_(last_checkpoint_),
      last_flush_(start_) {}

void StoreSink::begin(const std::vector<CurveColumn>& columns, const api::Resume* resume) {
  columns_ = columns;
  curve_csv_ = api::curve_csv_header(columns);
  if (resume) {
    // The rows up to the checkpoint are in the store: the whole curve, when the job ends, starts with them.
    auto kept = api::resumed_curve(store_.live_curve_csv(job_).value_or(curve_csv_), resume->rows);
    if (!kept)
      throw CheckpointError("the store holds fewer curve rows than the " + std::to_string(resume->rows) +
                            " the checkpoint follows");
    curve_csv_ = std::move(*kept);
    // The same rows with their values (the checkpoint follows them, so the store holds them all).
    rows_ = store_.live_rows(job_).value_or(std::make_pair(std::string(), std::vector<api::StoredRow>())).second;
    rows_.resize(std::min(rows_.size(), resume->rows));
    rows_stored_ = resume->rows;
    return;
  }
  store_.start_curve(job_, curve_csv_);
}

bool StoreSink::checkpoint_due() {
  if (checkpoint_seconds_ <= 0) return false;
  return stopping_ || seconds_since(last_checkpoint_) >= checkpoint_seconds_;
}

void StoreSink::checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) {
  const auto t = std::chrono::steady_clock::now();
  // The state goes into the store a chunk at a time, each in its own transaction, beside the previous
  // checkpoint; then one transaction makes it the job's together with the rows and snapshots it follows.
  JobStore::Checkpoint cp{store_.begin_checkpoint(job_), 0, 0, std::int64_t(rows), std::int64_t(snapshots),
                          engine_version_};
  try {
    CheckpointWriter w([&](const char* data, std::size_t n) {
      if (!store_.put_checkpoint_chunk(job_, cp.generation, cp.chunks++, data, n))
        throw std::logic_error("checkpoint write abandoned");  // one run per job: cannot happen
      cp.bytes += std::int64_t(n);
    });
    content(w);
    w.finish();
    store_.append_results(job_, rows_stored_, pending_rows_, pending_snapshots_, &cp);
  } catch (...) {
    store_.end_checkpoint_write(job_, cp.generation);  // what it wrote is garbage now
    throw;
  }
  store_.end_checkpoint_write(job_, cp.generation);
  // The previous checkpoint's chunks, a chunk per transaction; not on the way out (the next start, or the
  // job's end, removes them), and a store that cannot delete now keeps them for the next time.
  if (!stopping_) {
    try {
      store_.drop_checkpoint_garbage(std::size_t(-1));
    } catch (const std::exception&) {
    }
  }
  rows_stored_ += pending_rows_.size();
  pending_rows_.clear();
  pending_snapshots_.clear();
  flush_seconds_total_ += seconds_since(t);
  ++checkpoints_;
  last_checkpoint_ = last_flush_ = std::chrono::steady_clock::now();
  if (stopping_) throw Interrupted();  // the shutdown's last checkpoint is stored: stop now
}

void StoreSink::curve_row(const std::vector<double>& values) {
  api::StoredRow row{api::curve_csv_line(columns_, values), api::curve_row_values(columns_, values)};
  curve_csv_ += row.csv;
  rows_.push_back(row);
  pending_rows_.push_back(std::move(row));
}

void StoreSink::snapshot(std::size_t index, const GrainSnapshot& s) {
  pending_snapshots_.push_back({int(index), s.strain, api::snapshot_json(s).dump()});
}

void StoreSink::flush() {
  if (pending_rows_.empty() && pending_snapshots_.empty()) return;
  const auto t = std::chrono::steady_clock::now();
  store_.append_results(job_, rows_stored_, pending_rows_, pending_snapshots_);
  rows_stored_ += pending_rows_.size();
  pending_rows_.clear();
  pending_snapshots_.clear();
  flush_seconds_total_ += seconds_since(t);
  ++flushes_;
}

bool StoreSink::progress(double fraction) {
  if (stopping_) {
    // Shutdown: the run goes on to its next safe point (the same loop iteration in every experiment)
    // to store a last checkpoint, then stops; without checkpoints, or if none comes within half a
    // second, it stops here and resumes from the previous one.
    if (checkpoint_seconds_ <= 0) throw Interrupted();
    if (!stop_seen_) stop_seen_ = std::chrono::steady_clock::now();
    if (seconds_since(*stop_seen_) > 0.5) throw Interrupted();
    return true;
  }
  if (seconds_since(last_flush_) < flush_seconds_) return true;
  flush();
  last_flush_ = std::chrono::steady_clock::now();
  const double elapsed = seconds_since(start_);
  store_.set_progress(job_, fraction, fraction > 0 ? elapsed * (1 - fraction) / fraction : -1);
  return !store_.cancel_requested(job_);
}

void StoreSink::summary(const nlohmann::json& summary) {
  flush();
  store_.succeed(job_, summary.dump(), curve_csv_, api::curve_rows_to_json(curve_csv_, rows_).dump());
}

}  // namespace granulab::server
