// JobStore on SQLite (see job_store.h). Each public method takes the mutex, and each state change runs
// inside one sqlite::Transaction together with its event, so either all of it lands or none does.
#include "server/store/job_store.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "server/store/job_rows.h"
#include "server/store/migrations.h"
#include "server/store/sqlite.h"
#include "server/store/store_clock.h"

namespace granulab::server {

using sqlite::Statement;
using sqlite::Transaction;

JobStore::JobStore(const std::string& path, std::int64_t max_bytes)
    : db_(std::make_unique<sqlite::Database>(path)), max_bytes_(max_bytes) {
  migrate(*db_);
  make_reserve();
  if (max_bytes > 0) {
    // SQLite refuses to grow the file past max_page_count pages (SQLITE_FULL, as on a full disk).
    sqlite::Statement size(*db_, "PRAGMA page_size");
    const std::int64_t page = size.step() ? size.column_int64(0) : 4096;
    db_->exec("PRAGMA max_page_count = " + std::to_string(std::max<std::int64_t>(1, max_bytes / page)));
  }
  // The write-ahead log keeps its size after a checkpoint unless told: truncated to 1 MB then, so that the
  // room the store counts (the file and its log, JobStore::space) comes back once the log is written out.
  db_->exec("PRAGMA journal_size_limit = 1048576");
}

JobStore::~JobStore() = default;

std::int64_t JobStore::submit(const std::string& spec_json, const std::string& experiment, const std::string& label,
                              const std::string& spec_hash, const std::string& engine_version, const std::string& owner,
                              int priority, double expected_bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(*db_,
               "INSERT INTO jobs (status, label, experiment, spec_json, spec_hash, engine_version, owner, priority, "
               "created_ms, expected_bytes) VALUES ('queued', ?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
  st.bind(1, label).bind(2, experiment).bind(3, spec_json).bind(4, spec_hash).bind(5, engine_version);
  st.bind(6, owner).bind(7, priority).bind(8, now_ms()).bind(9, expected_bytes);
  st.run();
  const std::int64_t id = db_->last_insert_rowid();
  log_event_locked(id, "submitted",
                   experiment + (label.empty() ? "" : " \"" + label + "\"") + ", priority " + std::to_string(priority));
  tx.commit();
  return id;
}

std::optional<JobRecord> JobStore::claim_next(int max_running_per_owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  std::int64_t id = 0;
  {
    // The best queued job whose owner is under the running quota; an owner at the quota waits, others pass.
    // Fair share within a priority: the owner with the fewest jobs running goes first, then the one whose
    // last job started longest ago (never: first), then the oldest job, so that one user's hundred queued
    // jobs take turns with another's first rather than run before it.
    Statement pick(*db_,
                   "SELECT id FROM jobs AS q WHERE status = 'queued' AND (?1 <= 0 OR (SELECT count(*) FROM jobs AS r "
                   "WHERE r.owner = q.owner AND r.status = 'running') < ?1) ORDER BY priority DESC, "
                   "(SELECT count(*) FROM jobs AS r WHERE r.owner = q.owner AND r.status = 'running') ASC, "
                   "(SELECT coalesce(max(s.started_ms), 0) FROM jobs AS s WHERE s.owner = q.owner) ASC, id ASC "
                   "LIMIT 1");
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

bool JobStore::finish_locked(std::int64_t id, JobStatus to, std::initializer_list<JobStatus> from,
                             const std::string& event) {
  const std::optional<JobStatus> now = status_locked(id);
  if (!now || std::find(from.begin(), from.end(), *now) == from.end()) return false;
  Statement st(*db_, "UPDATE jobs SET status = ?2, eta_seconds = -1, finished_ms = ?3 WHERE id = ?1");
  st.bind(1, id).bind(2, api::status_name(to)).bind(3, now_ms()).run();
  log_event_locked(id, api::status_name(to), event);
  drop_checkpoint_locked(id);  // a finished job is never resumed
  settle_stored_bytes_locked(id);
  return true;
}

bool JobStore::succeed(std::int64_t id, const std::string& summary_json, const std::string& curve_csv,
                       const std::string& curve_json) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  if (!finish_locked(id, JobStatus::succeeded, {JobStatus::running}, "")) return false;
  Statement st(*db_, "UPDATE jobs SET progress = 1, eta_seconds = 0, summary_json = ?2, error = '' WHERE id = ?1");
  st.bind(1, id).bind(2, summary_json).run();
  Statement curve(*db_, "INSERT OR REPLACE INTO curves (job_id, csv, json) VALUES (?1, ?2, ?3)");
  curve.bind(1, id).bind(2, curve_csv).bind(3, curve_json).run();
  Statement rows(*db_, "DELETE FROM curve_rows WHERE job_id = ?1");  // the whole curve replaces them
  rows.bind(1, id).run();
  settle_stored_bytes_locked(id);  // with the whole curve and summary now
  tx.commit();
  return true;
}

bool JobStore::fail(std::int64_t id, const std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  if (!finish_locked(id, JobStatus::failed, {JobStatus::queued, JobStatus::running}, error)) return false;
  Statement st(*db_, "UPDATE jobs SET error = ?2 WHERE id = ?1");
  st.bind(1, id).bind(2, error).run();
  tx.commit();
  return true;
}

bool JobStore::mark_cancelled(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  if (!finish_locked(id, JobStatus::cancelled, {JobStatus::queued, JobStatus::running}, "stopped by its worker"))
    return false;
  tx.commit();
  return true;
}

JobStore::CancelResult JobStore::request_cancel(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  const std::optional<JobStatus> found = status_locked(id);
  if (!found) return CancelResult::not_found;
  CancelResult result;
  if (finish_locked(id, JobStatus::cancelled, {JobStatus::queued}, "cancelled while queued")) {
    result = CancelResult::cancelled_queued;
  } else if (*found == JobStatus::running) {
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
  const std::optional<JobStatus> found = status_locked(id);
  if (!found) return WriteResult::not_found;
  if (!api::is_finished(*found)) return WriteResult::wrong_state;
  for (const char* sql : {"DELETE FROM snapshots WHERE job_id = ?1", "DELETE FROM curve_rows WHERE job_id = ?1",
                          "DELETE FROM curves WHERE job_id = ?1", "DELETE FROM checkpoints WHERE job_id = ?1",
                          "DELETE FROM jobs WHERE id = ?1"}) {
    Statement st(*db_, sql);
    st.bind(1, id).run();
  }
  log_event_locked(0, "deleted", "job " + std::to_string(id) + " (" + api::status_name(*found) + ") and its results");
  tx.commit();
  return WriteResult::done;
}

JobStore::WriteResult JobStore::set_priority(std::int64_t id, int priority) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  const std::optional<JobStatus> found = status_locked(id);
  if (!found) return WriteResult::not_found;
  if (*found != JobStatus::queued) return WriteResult::wrong_state;
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

std::vector<JobRecord> JobStore::list(std::optional<JobStatus> status_filter, int limit, std::int64_t offset,
                                      const std::string& owner_filter) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, std::string("SELECT ") + kJobListColumns +
                         " FROM jobs WHERE (?1 = '' OR status = ?1) AND (?4 = '' OR owner = ?4)"
                         " ORDER BY id DESC LIMIT ?2 OFFSET ?3");
  st.bind(1, status_filter ? api::status_name(*status_filter) : "")
      .bind(2, limit < 0 ? -1 : limit)
      .bind(3, std::max<std::int64_t>(offset, 0));
  st.bind(4, owner_filter);
  std::vector<JobRecord> jobs;
  while (st.step()) jobs.push_back(read_job(st));
  return jobs;
}

std::size_t JobStore::count(std::optional<JobStatus> status, const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT count(*) FROM jobs WHERE (?1 = '' OR status = ?1) AND (?2 = '' OR owner = ?2)");
  st.bind(1, status ? api::status_name(*status) : "").bind(2, owner);
  return st.step() ? static_cast<std::size_t>(st.column_int64(0)) : 0;
}

std::optional<std::int64_t> JobStore::find_succeeded(const std::string& spec_hash, const std::string& engine_version,
                                                     const std::optional<std::string>& owner) {
  if (spec_hash.empty()) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_,
               "SELECT id FROM jobs WHERE spec_hash = ?1 AND engine_version = ?2 AND status = 'succeeded' "
               "AND (?3 = 0 OR owner = ?4) ORDER BY id DESC LIMIT 1");
  st.bind(1, spec_hash).bind(2, engine_version).bind(3, owner ? 1 : 0).bind(4, owner.value_or(""));
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
    Statement st(
        *db_,
        "SELECT id FROM jobs WHERE status = 'running' AND cancel_requested = 1 AND slurm_job_id = '' ORDER BY id");
    while (st.step()) cancelled.push_back(st.column_int64(0));
    for (const std::int64_t id : cancelled)
      finish_locked(id, JobStatus::cancelled, {JobStatus::running}, "cancel requested before the daemon stopped");
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
                       "was running when the daemon stopped; resumes from its checkpoint after " +
                           std::to_string(rows) + " curve rows");
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

std::optional<JobStatus> JobStore::status_locked(std::int64_t id) {
  Statement st(*db_, "SELECT status FROM jobs WHERE id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  return api::parse_job_status(st.column_text(0)).value_or(JobStatus::failed);
}

void JobStore::drop_checkpoint_locked(std::int64_t id) {
  Statement st(*db_, "DELETE FROM checkpoints WHERE job_id = ?1");
  st.bind(1, id).run();
}

}  // namespace granulab::server
