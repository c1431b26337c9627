// JobStore: the state of jobs that run on a Slurm cluster (job_store.h, "Jobs on a Slurm cluster").
// Same rules as job_store.cpp: the mutex, one transaction per change, its event in the same transaction.
#include "server/store/job_store.h"
#include "server/store/sqlite.h"
#include "server/store/store_clock.h"

namespace granulab::server {

namespace {

using sqlite::Statement;
using sqlite::Transaction;

}  // namespace

std::vector<JobRecord> JobStore::unsubmitted(int limit) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::int64_t> ids;
  {
    Statement st(*db_,
                 "SELECT id FROM jobs WHERE status = 'queued' AND slurm_job_id = '' ORDER BY priority DESC, id ASC "
                 "LIMIT ?1");
    st.bind(1, limit);
    while (st.step()) ids.push_back(st.column_int64(0));
  }
  std::vector<JobRecord> out;
  for (const std::int64_t id : ids)
    if (auto job = get_locked(id)) out.push_back(std::move(*job));
  return out;
}

std::string JobStore::worker_token(std::int64_t id, const std::string& fresh) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!fresh.empty()) {
    Statement set(*db_, "UPDATE jobs SET worker_token = ?2 WHERE id = ?1 AND worker_token = ''");
    set.bind(1, id).bind(2, fresh).run();
  }
  Statement st(*db_, "SELECT worker_token FROM jobs WHERE id = ?1");
  st.bind(1, id);
  return st.step() ? st.column_text(0) : std::string();
}

bool JobStore::set_slurm_job(std::int64_t id, const std::string& slurm_job_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(*db_,
               "UPDATE jobs SET slurm_job_id = ?2, slurm_state = 'SUBMITTED', slurm_done = 0, "
               "slurm_attempts = slurm_attempts + 1 WHERE id = ?1 AND status = 'queued' AND slurm_job_id = ''");
  st.bind(1, id).bind(2, slurm_job_id).run();
  if (db_->changes() == 0) return false;
  log_event_locked(id, "submitted", "Slurm job " + slurm_job_id);
  tx.commit();
  return true;
}

std::vector<JobRecord> JobStore::on_cluster() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::int64_t> ids;
  {
    Statement st(*db_, "SELECT id FROM jobs WHERE slurm_done = 0 AND slurm_job_id != '' ORDER BY id");
    while (st.step()) ids.push_back(st.column_int64(0));
  }
  std::vector<JobRecord> out;
  for (const std::int64_t id : ids)
    if (auto job = get_locked(id)) out.push_back(std::move(*job));
  return out;
}

void JobStore::set_slurm_state(std::int64_t id, const std::string& slurm_job_id, const std::string& state, bool ended) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "UPDATE jobs SET slurm_state = ?2, slurm_done = ?3 WHERE id = ?1 AND slurm_job_id = ?4");
  st.bind(1, id).bind(2, state).bind(3, ended ? 1 : 0).bind(4, slurm_job_id).run();
}

bool JobStore::mark_running(std::int64_t id, const std::string& slurm_job_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement st(
      *db_,
      "UPDATE jobs SET status = 'running', started_ms = ?2, eta_seconds = -1 WHERE id = ?1 AND status = 'queued' "
      "AND (?3 = '' OR slurm_job_id = ?3)");
  st.bind(1, id).bind(2, now_ms()).bind(3, slurm_job_id).run();
  if (db_->changes() > 0) log_event_locked(id, "started", "on the cluster");
  const std::optional<JobStatus> status = status_locked(id);
  tx.commit();
  return status == JobStatus::running;
}

JobStore::Requeue JobStore::requeue_for_cluster(std::int64_t id, const std::string& reason, int max_attempts) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  bool cancel = false;
  int attempts = 0;
  {
    Statement st(*db_,
                 "SELECT cancel_requested, slurm_attempts FROM jobs WHERE id = ?1 AND status IN ('queued', 'running')");
    st.bind(1, id);
    if (!st.step()) return Requeue::not_active;
    cancel = st.column_int64(0) != 0;
    attempts = st.column_int(1);
  }
  // In the same transaction as the check: a cancel that came meanwhile is not lost to a new Slurm job.
  if (cancel || attempts >= max_attempts) {
    const std::string error = cancel ? ""
                                     : reason + "; it had " + std::to_string(attempts) +
                                           " Slurm jobs, the most one job may have (JobStore::kMaxSlurmAttempts)";
    finish_locked(id, cancel ? JobStatus::cancelled : JobStatus::failed, {JobStatus::queued, JobStatus::running},
                  cancel ? "cancel requested before it could be requeued" : error);
    Statement st(*db_, "UPDATE jobs SET error = ?2 WHERE id = ?1");
    st.bind(1, id).bind(2, error).run();
    tx.commit();
    return cancel ? Requeue::cancelled : Requeue::failed;
  }
  Statement st(*db_,
               "UPDATE jobs SET status = 'queued', slurm_job_id = '', slurm_state = ?2, eta_seconds = -1, "
               "started_ms = 0 WHERE id = ?1");
  st.bind(1, id).bind(2, "requeued: " + reason).run();
  log_event_locked(id, "requeued", reason);
  tx.commit();
  return Requeue::requeued;
}

std::vector<std::pair<std::int64_t, std::string>> JobStore::worker_secrets() {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_, "SELECT id, worker_token FROM jobs WHERE worker_token != '' AND status IN ('queued', 'running')");
  std::vector<std::pair<std::int64_t, std::string>> out;
  while (st.step()) out.emplace_back(st.column_int64(0), st.column_text(1));
  return out;
}

}  // namespace granulab::server
