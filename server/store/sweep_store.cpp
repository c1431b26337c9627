// JobStore: sweeps, created whole with their jobs in one transaction (see job_store.h).
#include "server/store/job_store.h"

#include <algorithm>

#include "server/store/job_rows.h"
#include "server/store/sqlite.h"
#include "server/store/store_clock.h"

namespace granulab::server {

using sqlite::Statement;
using sqlite::Transaction;

std::pair<std::int64_t, std::vector<std::int64_t>> JobStore::submit_sweep(const SweepRecord& sweep,
                                                                          const std::vector<SweepJob>& jobs,
                                                                          const std::string& engine_version,
                                                                          int priority) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  Statement s(
      *db_,
      "INSERT INTO sweeps (label, owner, mode, base_json, vary_json, created_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
  s.bind(1, sweep.label).bind(2, sweep.owner).bind(3, sweep.mode).bind(4, sweep.base_json).bind(5, sweep.vary_json);
  s.bind(6, now_ms()).run();
  const std::int64_t sweep_id = db_->last_insert_rowid();
  std::vector<std::int64_t> ids;
  Statement job(*db_,
                "INSERT INTO jobs (status, label, experiment, spec_json, spec_hash, engine_version, owner, priority, "
                "created_ms, sweep_id, sweep_values, expected_bytes) VALUES ('queued', ?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, "
                "?9, ?10, ?11)");
  for (const SweepJob& j : jobs) {
    job.reset();
    job.bind(1, j.label).bind(2, j.experiment).bind(3, j.spec_json).bind(4, j.spec_hash).bind(5, engine_version);
    job.bind(6, sweep.owner).bind(7, priority).bind(8, now_ms()).bind(9, sweep_id).bind(10, j.values_json);
    job.bind(11, j.expected_bytes).run();
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

}  // namespace granulab::server
