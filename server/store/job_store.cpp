// JobStore on SQLite (see job_store.h). Each public method takes the mutex, and each state change runs
// inside one sqlite::Transaction together with its event, so either all of it lands or none does.
#include "server/store/job_store.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "server/store/migrations.h"
#include "server/store/sqlite.h"
#include "server/store/store_clock.h"

namespace granulab::server {

namespace {

using sqlite::Statement;
using sqlite::Transaction;

// Column order of read_job().
constexpr const char* kJobColumns =
    "id, status, label, experiment, spec_json, spec_hash, engine_version, owner, error, summary_json, "
    "priority, progress, eta_seconds, created_ms, started_ms, finished_ms, cancel_requested, sweep_id, sweep_values, "
    "slurm_job_id, slurm_state, slurm_attempts";

JobRecord read_job(const Statement& st) {
  JobRecord r;
  r.id = st.column_int64(0);
  r.status = st.column_text(1);
  r.label = st.column_text(2);
  r.experiment = st.column_text(3);
  r.spec_json = st.column_text(4);
  r.spec_hash = st.column_text(5);
  r.engine_version = st.column_text(6);
  r.owner = st.column_text(7);
  r.error = st.column_text(8);
  r.summary_json = st.column_text(9);
  r.priority = st.column_int(10);
  r.progress = st.column_double(11);
  r.eta_seconds = st.column_double(12);
  r.created_ms = st.column_int64(13);
  r.started_ms = st.column_int64(14);
  r.finished_ms = st.column_int64(15);
  r.cancel_requested = st.column_int64(16) != 0;
  r.sweep_id = st.column_int64(17);
  r.sweep_values = st.column_text(18);
  r.slurm_job_id = st.column_text(19);
  r.slurm_state = st.column_text(20);
  r.slurm_attempts = st.column_int(21);
  return r;
}

}  // namespace

JobStore::JobStore(const std::string& path, std::int64_t max_bytes) : db_(std::make_unique<sqlite::Database>(path)) {
  migrate(*db_);
  if (max_bytes > 0) {
    // SQLite refuses to grow the file past max_page_count pages (SQLITE_FULL, as on a full disk).
    sqlite::Statement size(*db_, "PRAGMA page_size");
    const std::int64_t page = size.step() ? size.column_int64(0) : 4096;
    db_->exec("PRAGMA max_page_count = " + std::to_string(std::max<std::int64_t>(1, max_bytes / page)));
  }
}

JobStore::~JobStore() = default;

std::pair<std::int64_t, std::vector<std::int64_t>> JobStore::submit_sweep(const SweepRecord& sweep,
                                                                          const std::vector<SweepJob>& jobs,
                                                                          const std::string& engine_version, int priority) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement s(*db_,
              "INSERT INTO sweeps (label, owner, mode, base_json, vary_json, created_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
  s.bind(1, sweep.label).bind(2, sweep.owner).bind(3, sweep.mode).bind(4, sweep.base_json).bind(5, sweep.vary_json);
  s.bind(6, now_ms()).run();
  const std::int64_t sweep_id = db_->last_insert_rowid();
  std::vector<std::int64_t> ids;
  Statement job(*db_,
                "INSERT INTO jobs (status, label, experiment, spec_json, spec_hash, engine_version, owner, priority, "
                "created_ms, sweep_id, sweep_values) VALUES ('queued', ?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
  for (const SweepJob& j : jobs) {
    job.reset();
    job.bind(1, j.label).bind(2, j.experiment).bind(3, j.spec_json).bind(4, j.spec_hash).bind(5, engine_version);
    job.bind(6, sweep.owner).bind(7, priority).bind(8, now_ms()).bind(9, sweep_id).bind(10, j.values_json).run();
    ids.push_back(db_->last_insert_rowid());
  }
  log_event_locked(0, "sweep", "sweep " + std::to_string(sweep_id) + ": " + std::to_string(ids.size()) + " jobs");
  tx.commit();
  return {sweep_id, ids};
}

namespace {

constexpr const char* kSweepColumns = "id, label, owner, mode, base_json, vary_json, created_ms";

SweepRecord read_sweep(const Statement& st) {
  return {st.column_int64(0), st.column_text(1), st.column_text(2), st.column_text(3),
          st.column_text(4),  st.column_text(5), st.column_int64(6)};
}

}  // namespace

std::optional<SweepRecord> JobStore::get_sweep(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, std::string("SELECT ") + kSweepColumns + " FROM sweeps WHERE id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  return read_sweep(st);
}

std::vector<SweepRecord> JobStore::list_sweeps(int limit, std::int64_t offset, const std::string& owner_filter) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, std::string("SELECT ") + kSweepColumns +
                         " FROM sweeps WHERE (?3 = '' OR owner = ?3) ORDER BY id DESC LIMIT ?1 OFFSET ?2");
  st.bind(1, limit).bind(2, std::max<std::int64_t>(offset, 0)).bind(3, owner_filter);
  std::vector<SweepRecord> out;
  while (st.step()) out.push_back(read_sweep(st));
  return out;
}

std::vector<JobRecord> JobStore::sweep_jobs(std::int64_t sweep_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, std::string("SELECT ") + kJobColumns + " FROM jobs WHERE sweep_id = ?1 ORDER BY id");
  st.bind(1, sweep_id);
  std::vector<JobRecord> out;
  while (st.step()) out.push_back(read_job(st));
  return out;
}

std::int64_t JobStore::submit(const std::string& spec_json, const std::string& experiment, const std::string& label,
                              const std::string& spec_hash, const std::string& engine_version,
                              const std::string& owner, int priority) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(*db_,
               "INSERT INTO jobs (status, label, experiment, spec_json, spec_hash, engine_version, owner, priority, "
               "created_ms) VALUES ('queued', ?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
  st.bind(1, label).bind(2, experiment).bind(3, spec_json).bind(4, spec_hash).bind(5, engine_version);
  st.bind(6, owner).bind(7, priority).bind(8, now_ms());
  st.run();
  const std::int64_t id = db_->last_insert_rowid();
  log_event_locked(id, "submitted", experiment + (label.empty() ? "" : " \"" + label + "\"") + ", priority " +
                                        std::to_string(priority));
  tx.commit();
  return id;
}

std::optional<JobRecord> JobStore::claim_next(int max_running_per_owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  std::int64_t id = 0;
  {
    // The best queued job whose owner is under the running quota; an owner at the quota waits, others pass.
    Statement pick(*db_,
                   "SELECT id FROM jobs AS q WHERE status = 'queued' AND (?1 <= 0 OR (SELECT count(*) FROM jobs AS r "
                   "WHERE r.status = 'running' AND r.owner = q.owner) < ?1) ORDER BY priority DESC, id ASC LIMIT 1");
    pick.bind(1, max_running_per_owner);
    if (!pick.step()) return std::nullopt;
    id = pick.column_int64(0);
  }
  Statement take(*db_,
                 "UPDATE jobs SET status = 'running', started_ms = ?2, progress = 0, eta_seconds = -1, "
                 "cancel_requested = 0 WHERE id = ?1 AND status = 'queued'");
  take.bind(1, id).bind(2, now_ms()).run();
  log_event_locked(id, "started", "");
  auto job = get_locked(id);
  tx.commit();
  return job;
}

void JobStore::set_progress(std::int64_t id, double progress, double eta_seconds) {
  // NaN would be stored as NULL by SQLite; clamp and normalise before binding.
  progress = std::isfinite(progress) ? std::clamp(progress, 0.0, 1.0) : 0.0;
  if (!std::isfinite(eta_seconds) || eta_seconds < 0.0) eta_seconds = -1.0;
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "UPDATE jobs SET progress = ?2, eta_seconds = ?3 WHERE id = ?1 AND status = 'running'");
  st.bind(1, id).bind(2, progress).bind(3, eta_seconds).run();  // one statement: its own transaction
}

bool JobStore::succeed(std::int64_t id, const std::string& summary_json, const std::string& curve_csv,
                       const std::string& curve_json) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(*db_,
               "UPDATE jobs SET status = 'succeeded', progress = 1, eta_seconds = 0, summary_json = ?2, "
               "error = '', finished_ms = ?3 WHERE id = ?1 AND status = 'running'");
  st.bind(1, id).bind(2, summary_json).bind(3, now_ms()).run();
  if (db_->changes() == 0) return false;
  Statement curve(*db_, "INSERT OR REPLACE INTO curves (job_id, csv, json) VALUES (?1, ?2, ?3)");
  curve.bind(1, id).bind(2, curve_csv).bind(3, curve_json).run();
  Statement rows(*db_, "DELETE FROM curve_rows WHERE job_id = ?1");  // the whole curve replaces them
  rows.bind(1, id).run();
  log_event_locked(id, "succeeded", "");
  drop_checkpoint_locked(id);  // a finished job is never resumed
  tx.commit();
  return true;
}

bool JobStore::fail(std::int64_t id, const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(*db_,
               "UPDATE jobs SET status = 'failed', error = ?2, eta_seconds = -1, finished_ms = ?3 "
               "WHERE id = ?1 AND status IN ('queued', 'running')");
  st.bind(1, id).bind(2, error).bind(3, now_ms()).run();
  if (db_->changes() == 0) return false;
  log_event_locked(id, "failed", error);
  drop_checkpoint_locked(id);  // a finished job is never resumed
  tx.commit();
  return true;
}

bool JobStore::mark_cancelled(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(*db_,
               "UPDATE jobs SET status = 'cancelled', eta_seconds = -1, finished_ms = ?2 "
               "WHERE id = ?1 AND status IN ('queued', 'running')");
  st.bind(1, id).bind(2, now_ms()).run();
  if (db_->changes() == 0) return false;
  log_event_locked(id, "cancelled", "stopped by its worker");
  drop_checkpoint_locked(id);  // a finished job is never resumed
  tx.commit();
  return true;
}

JobStore::CancelResult JobStore::request_cancel(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  const std::optional<std::string> found = status_locked(id);
  if (!found) return CancelResult::not_found;
  const std::string& status = *found;
  CancelResult result;
  if (status == "queued") {
    Statement st(*db_, "UPDATE jobs SET status = 'cancelled', eta_seconds = -1, finished_ms = ?2 WHERE id = ?1");
    st.bind(1, id).bind(2, now_ms()).run();
    log_event_locked(id, "cancelled", "cancelled while queued");
  drop_checkpoint_locked(id);  // a finished job is never resumed
    result = CancelResult::cancelled_queued;
  } else if (status == "running") {
    Statement st(*db_, "UPDATE jobs SET cancel_requested = 1 WHERE id = ?1");
    st.bind(1, id).run();
    log_event_locked(id, "cancel_requested", "");
    result = CancelResult::requested_running;
  } else {
    return CancelResult::wrong_state;
  }
  tx.commit();
  return result;
}

JobStore::WriteResult JobStore::remove(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  const std::optional<std::string> found = status_locked(id);
  if (!found) return WriteResult::not_found;
  const std::string& status = *found;
  if (status == "queued" || status == "running") return WriteResult::wrong_state;
  for (const char* sql : {"DELETE FROM snapshots WHERE job_id = ?1", "DELETE FROM curve_rows WHERE job_id = ?1",
                          "DELETE FROM curves WHERE job_id = ?1", "DELETE FROM checkpoints WHERE job_id = ?1",
                          "DELETE FROM jobs WHERE id = ?1"}) {
    Statement st(*db_, sql);
    st.bind(1, id).run();
  }
  log_event_locked(0, "deleted", "job " + std::to_string(id) + " (" + status + ") and its results");
  tx.commit();
  return WriteResult::done;
}

JobStore::WriteResult JobStore::set_priority(std::int64_t id, int priority) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  const std::optional<std::string> found = status_locked(id);
  if (!found) return WriteResult::not_found;
  const std::string& status = *found;
  if (status != "queued") return WriteResult::wrong_state;
  Statement st(*db_, "UPDATE jobs SET priority = ?2 WHERE id = ?1");
  st.bind(1, id).bind(2, priority).run();
  log_event_locked(id, "priority", std::to_string(priority));
  tx.commit();
  return WriteResult::done;
}

bool JobStore::cancel_requested(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT cancel_requested FROM jobs WHERE id = ?1");
  st.bind(1, id);
  return st.step() && st.column_int64(0) != 0;
}

std::optional<JobRecord> JobStore::get(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  return get_locked(id);
}

std::optional<JobRecord> JobStore::get_locked(std::int64_t id) {
  Statement st(*db_, std::string("SELECT ") + kJobColumns + " FROM jobs WHERE id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  return read_job(st);
}

std::vector<JobRecord> JobStore::list(const std::string& status_filter, int limit, std::int64_t offset,
                                      const std::string& owner_filter) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, std::string("SELECT ") + kJobColumns +
                         " FROM jobs WHERE (?1 = '' OR status = ?1) AND (?4 = '' OR owner = ?4)"
                         " ORDER BY id DESC LIMIT ?2 OFFSET ?3");
  st.bind(1, status_filter).bind(2, limit < 0 ? -1 : limit).bind(3, std::max<std::int64_t>(offset, 0));
  st.bind(4, owner_filter);
  std::vector<JobRecord> jobs;
  while (st.step()) jobs.push_back(read_job(st));
  return jobs;
}

std::size_t JobStore::count(const std::string& status, const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT count(*) FROM jobs WHERE (?1 = '' OR status = ?1) AND (?2 = '' OR owner = ?2)");
  st.bind(1, status).bind(2, owner);
  return st.step() ? static_cast<std::size_t>(st.column_int64(0)) : 0;
}

std::optional<std::string> JobStore::curve_column(std::int64_t id, const char* column) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, std::string("SELECT ") + column + " FROM curves WHERE job_id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  return st.column_text(0);
}

std::optional<std::string> JobStore::curve_csv(std::int64_t id) { return curve_column(id, "csv"); }

std::optional<std::string> JobStore::curve_json(std::int64_t id) { return curve_column(id, "json"); }

void JobStore::start_curve(std::int64_t id, const std::string& header) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  // A run from the start: nothing of an earlier run may be mixed in or resumed from later.
  for (const char* sql : {"DELETE FROM curve_rows WHERE job_id = ?1", "DELETE FROM snapshots WHERE job_id = ?1",
                          "DELETE FROM checkpoints WHERE job_id = ?1"}) {
    Statement drop(*db_, sql);
    drop.bind(1, id).run();
  }
  Statement st(*db_, "UPDATE jobs SET curve_header = ?2 WHERE id = ?1");
  st.bind(1, id).bind(2, header).run();
  tx.commit();
}

void JobStore::append_results(std::int64_t id, std::size_t first_index, const std::vector<std::string>& lines,
                              const std::vector<SnapshotBlob>& snapshots, const Checkpoint* checkpoint) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  {
    Statement st(*db_, "SELECT 1 FROM jobs WHERE id = ?1 AND status = 'running'");
    st.bind(1, id);
    if (!st.step()) return;
  }
  Statement row(*db_, "INSERT OR REPLACE INTO curve_rows (job_id, idx, line) VALUES (?1, ?2, ?3)");
  for (std::size_t k = 0; k < lines.size(); ++k) {
    row.reset();
    row.bind(1, id).bind(2, std::int64_t(first_index + k)).bind(3, lines[k]).run();
  }
  Statement snap(*db_,
                 "INSERT INTO snapshots (job_id, idx, strain, data) VALUES (?1, ?2, ?3, ?4) "
                 "ON CONFLICT (job_id, idx) DO UPDATE SET strain = excluded.strain, data = excluded.data");
  for (const SnapshotBlob& b : snapshots) {
    snap.reset();
    snap.bind(1, id).bind(2, b.index).bind(3, b.strain);
    snap.bind_blob(4, std::vector<std::uint8_t>(b.data.begin(), b.data.end())).run();
  }
  if (checkpoint) {
    Statement cp(*db_,
                 "INSERT OR REPLACE INTO checkpoints (job_id, state, rows, snapshots, engine_version, at_ms) "
                 "VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
    cp.bind(1, id).bind_blob(2, std::vector<std::uint8_t>(checkpoint->state.begin(), checkpoint->state.end()));
    cp.bind(3, checkpoint->rows).bind(4, checkpoint->snapshots).bind(5, checkpoint->engine_version).bind(6, now_ms()).run();
  }
  tx.commit();
}

std::optional<JobStore::Checkpoint> JobStore::checkpoint(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT state, rows, snapshots, engine_version FROM checkpoints WHERE job_id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  const std::vector<std::uint8_t> blob = st.column_blob(0);
  return Checkpoint{std::string(blob.begin(), blob.end()), st.column_int64(1), st.column_int64(2), st.column_text(3)};
}

void JobStore::trim_results(std::int64_t id, std::int64_t rows, std::int64_t snapshots) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement r(*db_, "DELETE FROM curve_rows WHERE job_id = ?1 AND idx >= ?2");
  r.bind(1, id).bind(2, rows).run();
  Statement s(*db_, "DELETE FROM snapshots WHERE job_id = ?1 AND idx >= ?2");
  s.bind(1, id).bind(2, snapshots).run();
  log_event_locked(id, "resumed", "from its checkpoint after " + std::to_string(rows) + " curve rows");
  tx.commit();
}

void JobStore::discard_partial_results(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  for (const char* sql : {"DELETE FROM checkpoints WHERE job_id = ?1", "DELETE FROM snapshots WHERE job_id = ?1",
                          "DELETE FROM curve_rows WHERE job_id = ?1"}) {
    Statement st(*db_, sql);
    st.bind(1, id).run();
  }
  tx.commit();
}

std::optional<std::string> JobStore::live_curve_csv(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  {
    Statement whole(*db_, "SELECT csv FROM curves WHERE job_id = ?1");
    whole.bind(1, id);
    if (whole.step()) return whole.column_text(0);
  }
  std::string csv;
  {
    Statement header(*db_, "SELECT curve_header FROM jobs WHERE id = ?1");
    header.bind(1, id);
    if (!header.step()) return std::nullopt;
    csv = header.column_text(0);
  }
  if (csv.empty()) return std::nullopt;
  Statement rows(*db_, "SELECT line FROM curve_rows WHERE job_id = ?1 ORDER BY idx");
  rows.bind(1, id);
  while (rows.step()) csv += rows.column_text(0);
  return csv;
}

std::optional<std::pair<std::string, std::string>> JobStore::latest_row(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement header(*db_, "SELECT curve_header FROM jobs WHERE id = ?1");
  header.bind(1, id);
  if (!header.step()) return std::nullopt;
  std::string head = header.column_text(0);
  Statement last(*db_, "SELECT line FROM curve_rows WHERE job_id = ?1 ORDER BY idx DESC LIMIT 1");
  last.bind(1, id);
  if (head.empty() || !last.step()) return std::nullopt;
  return std::make_pair(std::move(head), last.column_text(0));
}

void JobStore::add_snapshot(std::int64_t job_id, int index, double strain, const std::vector<std::uint8_t>& blob) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_,
               "INSERT INTO snapshots (job_id, idx, strain, data) VALUES (?1, ?2, ?3, ?4) "
               "ON CONFLICT (job_id, idx) DO UPDATE SET strain = excluded.strain, data = excluded.data");
  st.bind(1, job_id).bind(2, index).bind(3, strain).bind_blob(4, blob).run();
}

std::vector<SnapshotInfo> JobStore::snapshots(std::int64_t job_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  // length() of a BLOB is read from the record header: the data itself is not loaded.
  Statement st(*db_, "SELECT idx, strain, length(data) FROM snapshots WHERE job_id = ?1 ORDER BY idx");
  st.bind(1, job_id);
  std::vector<SnapshotInfo> out;
  while (st.step()) {
    out.push_back({st.column_int(0), st.column_double(1), static_cast<std::size_t>(st.column_int64(2))});
  }
  return out;
}

std::optional<std::vector<std::uint8_t>> JobStore::snapshot(std::int64_t job_id, int index) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT data FROM snapshots WHERE job_id = ?1 AND idx = ?2");
  st.bind(1, job_id).bind(2, index);
  if (!st.step()) return std::nullopt;
  return st.column_blob(0);
}

std::optional<std::int64_t> JobStore::find_succeeded(const std::string& spec_hash, const std::string& engine_version) {
  if (spec_hash.empty()) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_,
               "SELECT id FROM jobs WHERE spec_hash = ?1 AND engine_version = ?2 AND status = 'succeeded' "
               "ORDER BY id DESC LIMIT 1");
  st.bind(1, spec_hash).bind(2, engine_version);
  if (!st.step()) return std::nullopt;
  return st.column_int64(0);
}

std::size_t JobStore::requeue_running(bool keep_cluster_jobs) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  std::vector<std::int64_t> ids;
  if (!keep_cluster_jobs) {
    // This daemon runs jobs itself: a Slurm job still running one of them could only collide with it, so
    // its worker's secret is revoked (its requests get 403) and the job is no longer on the cluster.
    Statement st(*db_,
                 "UPDATE jobs SET slurm_job_id = '', worker_token = '', slurm_done = 1 "
                 "WHERE status IN ('queued', 'running') AND slurm_job_id != ''");
    st.run();
  }
  {
    // A cancel asked for before the stop is honoured, not forgotten: the job ends cancelled, with what it
    // had computed.
    std::vector<std::int64_t> cancelled;
    Statement st(*db_, "SELECT id FROM jobs WHERE status = 'running' AND cancel_requested = 1 AND slurm_job_id = '' ORDER BY id");
    while (st.step()) cancelled.push_back(st.column_int64(0));
    for (const std::int64_t id : cancelled) {
      Statement job(*db_, "UPDATE jobs SET status = 'cancelled', eta_seconds = -1, finished_ms = ?2 WHERE id = ?1");
      job.bind(1, id).bind(2, now_ms()).run();
      log_event_locked(id, "cancelled", "cancel requested before the daemon stopped");
  drop_checkpoint_locked(id);  // a finished job is never resumed
    }
  }
  {
    Statement st(*db_, "SELECT id FROM jobs WHERE status = 'running' AND slurm_job_id = '' ORDER BY id");
    while (st.step()) ids.push_back(st.column_int64(0));
  }
  for (const std::int64_t id : ids) {
    Statement has(*db_, "SELECT rows FROM checkpoints WHERE job_id = ?1");
    has.bind(1, id);
    if (has.step()) {
      // It resumes from its checkpoint: the results up to it stay (those after it are trimmed then).
      const std::int64_t rows = has.column_int64(0);
      Statement job(*db_,
                    "UPDATE jobs SET status = 'queued', eta_seconds = -1, started_ms = 0, cancel_requested = 0 "
                    "WHERE id = ?1");
      job.bind(1, id).run();
      log_event_locked(id, "requeued",
                       "was running when the daemon stopped; resumes from its checkpoint after " + std::to_string(rows) +
                           " curve rows");
      continue;
    }
    Statement job(*db_,
                  "UPDATE jobs SET status = 'queued', progress = 0, eta_seconds = -1, started_ms = 0, "
                  "cancel_requested = 0 WHERE id = ?1");
    job.bind(1, id).run();
    // Results of the interrupted run would mix with the rerun's: drop them.
    Statement snaps(*db_, "DELETE FROM snapshots WHERE job_id = ?1");
    snaps.bind(1, id).run();
    Statement rows(*db_, "DELETE FROM curve_rows WHERE job_id = ?1");
    rows.bind(1, id).run();
    Statement header(*db_, "UPDATE jobs SET curve_header = '' WHERE id = ?1");
    header.bind(1, id).run();
    log_event_locked(id, "requeued", "was running when the daemon stopped; back in the queue");
  }
  if (!ids.empty()) {
    log_event_locked(0, "requeued", std::to_string(ids.size()) + " interrupted job(s) back in the queue");
  }
  tx.commit();
  return ids.size();
}

void JobStore::log_event(std::int64_t job_id, const std::string& kind, const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  log_event_locked(job_id, kind, message);
}

std::optional<std::string> JobStore::status_locked(std::int64_t id) {
  Statement st(*db_, "SELECT status FROM jobs WHERE id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  return st.column_text(0);
}

void JobStore::drop_checkpoint_locked(std::int64_t id) {
  Statement st(*db_, "DELETE FROM checkpoints WHERE job_id = ?1");
  st.bind(1, id).run();
}

void JobStore::log_event_locked(std::int64_t job_id, const std::string& kind, const std::string& message) {
  Statement st(*db_, "INSERT INTO events (job_id, at_ms, kind, message) VALUES (?1, ?2, ?3, ?4)");
  if (job_id == 0) {
    st.bind_null(1);
  } else {
    st.bind(1, job_id);
  }
  st.bind(2, now_ms()).bind(3, kind).bind(4, message).run();
}

std::vector<std::string> JobStore::events(std::int64_t job_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT kind, message FROM events WHERE job_id IS ?1 ORDER BY id");
  if (job_id == 0) {
    st.bind_null(1);
  } else {
    st.bind(1, job_id);
  }
  std::vector<std::string> out;
  while (st.step()) out.push_back(st.column_text(0) + ": " + st.column_text(1));
  return out;
}

}  // namespace granulab::server
