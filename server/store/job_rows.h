// How a jobs row is read (the store's files share it; not part of the store's interface).
#pragma once

#include "server/store/job_store.h"
#include "server/store/sqlite.h"

namespace granulab::server {

// Column order of read_job().
inline constexpr const char* kJobColumns =
    "id, status, label, experiment, spec_json, spec_hash, engine_version, owner, error, summary_json, "
    "priority, progress, eta_seconds, created_ms, started_ms, finished_ms, cancel_requested, sweep_id, sweep_values, "
    "slurm_job_id, slurm_state, slurm_attempts";

// The same for listings, which never show a spec: its text (up to a request body, each) is not read at all.
inline constexpr const char* kJobListColumns =
    "id, status, label, experiment, '' AS spec_json, spec_hash, engine_version, owner, error, summary_json, "
    "priority, progress, eta_seconds, created_ms, started_ms, finished_ms, cancel_requested, sweep_id, sweep_values, "
    "slurm_job_id, slurm_state, slurm_attempts";

inline JobRecord read_job(const sqlite::Statement& st) {
  JobRecord r;
  r.id = st.column_int64(0);
  r.status = api::parse_job_status(st.column_text(1)).value_or(JobStatus::failed);  // the schema allows no other
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

}  // namespace granulab::server
