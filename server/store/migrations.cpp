// The job store's schema, as versioned migrations. PRAGMA user_version holds how many have been applied;
// migrate() applies the missing ones in order, one transaction each (the schema change and the version
// bump commit together, so a crash leaves either the old or the new version, never a mix).
// Never edit a migration that has shipped: append a new one.
#include "server/store/migrations.h"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace granulab::server {

namespace {

// Times are Unix epoch milliseconds; 0 means "not yet". eta_seconds < 0 means "unknown".
// Job ids come from AUTOINCREMENT, so they grow with submission order and are never reused: "oldest
// first" is "smallest id first".
const char* const kMigrations[] = {
    // 1: jobs, their curves, snapshots and event log.
    R"sql(
CREATE TABLE jobs (
  id               INTEGER PRIMARY KEY AUTOINCREMENT,
  status           TEXT    NOT NULL DEFAULT 'queued'
                   CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
  label            TEXT    NOT NULL DEFAULT '',
  experiment       TEXT    NOT NULL,
  spec_json        TEXT    NOT NULL,
  spec_hash        TEXT    NOT NULL DEFAULT '',
  engine_version   TEXT    NOT NULL DEFAULT '',
  owner            TEXT    NOT NULL DEFAULT '',
  priority         INTEGER NOT NULL DEFAULT 0,
  progress         REAL    NOT NULL DEFAULT 0,
  eta_seconds      REAL    NOT NULL DEFAULT -1,
  error            TEXT    NOT NULL DEFAULT '',
  summary_json     TEXT    NOT NULL DEFAULT '',
  created_ms       INTEGER NOT NULL,
  started_ms       INTEGER NOT NULL DEFAULT 0,
  finished_ms      INTEGER NOT NULL DEFAULT 0,
  cancel_requested INTEGER NOT NULL DEFAULT 0 CHECK (cancel_requested IN (0, 1))
);
-- Status filters, and the claim order (highest priority, then oldest) read straight off the index.
CREATE INDEX jobs_by_status ON jobs (status, priority DESC, id);
CREATE INDEX jobs_by_spec ON jobs (spec_hash, engine_version);

CREATE TABLE curves (
  job_id INTEGER PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
  csv    TEXT NOT NULL,
  json   TEXT NOT NULL
);

CREATE TABLE snapshots (
  job_id INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
  idx    INTEGER NOT NULL,
  strain REAL    NOT NULL,
  data   BLOB    NOT NULL,
  PRIMARY KEY (job_id, idx)
);

-- job_id NULL: an event about the daemon, not about one job.
CREATE TABLE events (
  id      INTEGER PRIMARY KEY AUTOINCREMENT,
  job_id  INTEGER REFERENCES jobs (id) ON DELETE CASCADE,
  at_ms   INTEGER NOT NULL,
  kind    TEXT    NOT NULL,
  message TEXT    NOT NULL DEFAULT ''
);
CREATE INDEX events_by_job ON events (job_id, id);
)sql",
    // 2: live results. Curve rows as a running job makes them (one CSV line each, in order), under the
    // header the job's experiment gave; on success the whole curve moves to `curves`.
    R"sql(
ALTER TABLE jobs ADD COLUMN curve_header TEXT NOT NULL DEFAULT '';
CREATE TABLE curve_rows (
  job_id INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
  idx    INTEGER NOT NULL,
  line   TEXT    NOT NULL,
  PRIMARY KEY (job_id, idx)
) WITHOUT ROWID;
)sql",
    // 3: checkpoints. A running job's last checkpoint (the engine's state and the counts of rows and
    // snapshots it goes with), written in the same transaction as those rows: a restart resumes from it.
    R"sql(
CREATE TABLE checkpoints (
  job_id         INTEGER PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
  state          BLOB    NOT NULL,
  rows           INTEGER NOT NULL,
  snapshots      INTEGER NOT NULL,
  engine_version TEXT    NOT NULL,
  at_ms          INTEGER NOT NULL
);
)sql",
    // 4: sweeps. A sweep is its request (base spec, varied lists, mode); its jobs are ordinary jobs that
    // name it and the values of their point.
    R"sql(
CREATE TABLE sweeps (
  id         INTEGER PRIMARY KEY,
  label      TEXT    NOT NULL DEFAULT '',
  owner      TEXT    NOT NULL DEFAULT '',
  mode       TEXT    NOT NULL,
  base_json  TEXT    NOT NULL,
  vary_json  TEXT    NOT NULL,
  created_ms INTEGER NOT NULL
);
ALTER TABLE jobs ADD COLUMN sweep_id INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN sweep_values TEXT NOT NULL DEFAULT '';
CREATE INDEX jobs_by_sweep ON jobs (sweep_id, id);
)sql",
    // 5: jobs on a Slurm cluster (server/slurm/). slurm_job_id: the Slurm job that runs it ("123", or "123_4"
    // for task 4 of array 123), '' when none; slurm_state: Slurm's latest word on it ("PENDING (Priority)");
    // slurm_done: that Slurm job has ended; slurm_attempts: Slurm jobs it was given (a requeue after a time
    // limit gives another); worker_token: the secret its worker presents to the daemon.
    R"sql(
ALTER TABLE jobs ADD COLUMN slurm_job_id TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN slurm_state TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN slurm_done INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN slurm_attempts INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN worker_token TEXT NOT NULL DEFAULT '';
CREATE INDEX jobs_on_cluster ON jobs (slurm_done, slurm_job_id);
)sql",
    // 6: each live curve row's values as its CSV line reads them (a JSON array), so that a curve's JSON is
    // built from numbers, not from CSV text; '' for rows stored before (they are read from their line).
    R"sql(
ALTER TABLE curve_rows ADD COLUMN row_values TEXT NOT NULL DEFAULT '';
)sql",
    // 7: the fair queue (JobStore::claim_next) asks, per queued owner, how many of theirs run and when
    // theirs last started.
    R"sql(
CREATE INDEX jobs_by_owner ON jobs (owner, status, started_ms);
)sql",
    // 8: what each job is expected to store at most (results and checkpoints, B), counted against the
    // store's room while it is queued or running, so that a submission the store cannot hold is refused.
    R"sql(
ALTER TABLE jobs ADD COLUMN expected_bytes REAL NOT NULL DEFAULT 0;
)sql",
    // 9: checkpoints in chunks (JobStore::Checkpoint): one blob per checkpoint failed above ~1 GB
    // (SQLite's limit) and held the whole state in memory. A chunk belongs to its checkpoint by generation;
    // no foreign key, so that deleting a job never drops gigabytes in one transaction (the chunks become
    // garbage, removed a chunk at a time). The stored checkpoints become generation 1, one chunk each.
    R"sql(
CREATE TABLE checkpoint_chunks (
  job_id     INTEGER NOT NULL,
  generation INTEGER NOT NULL,
  idx        INTEGER NOT NULL,
  data       BLOB    NOT NULL,
  PRIMARY KEY (job_id, generation, idx)
);
CREATE TABLE checkpoints_chunked (
  job_id         INTEGER PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
  generation     INTEGER NOT NULL,
  chunks         INTEGER NOT NULL,
  bytes          INTEGER NOT NULL,
  rows           INTEGER NOT NULL,
  snapshots      INTEGER NOT NULL,
  engine_version TEXT    NOT NULL,
  at_ms          INTEGER NOT NULL
);
INSERT INTO checkpoint_chunks (job_id, generation, idx, data) SELECT job_id, 1, 0, state FROM checkpoints;
INSERT INTO checkpoints_chunked SELECT job_id, 1, 1, length(state), rows, snapshots, engine_version, at_ms
  FROM checkpoints;
DROP TABLE checkpoints;
ALTER TABLE checkpoints_chunked RENAME TO checkpoints;
)sql",
};

constexpr std::size_t kMigrationCount = sizeof(kMigrations) / sizeof(kMigrations[0]);

std::int64_t user_version(sqlite::Database& db) {
  sqlite::Statement st(db, "PRAGMA user_version");
  return st.step() ? st.column_int64(0) : 0;
}

}  // namespace

std::size_t schema_version_latest() { return kMigrationCount; }

void migrate(sqlite::Database& db) {
  for (;;) {
    // The version is read inside the write transaction: a second process migrating the same file at the
    // same moment waits for the lock, then sees the bumped version and skips the step.
    sqlite::Transaction tx(db);
    const std::int64_t version = user_version(db);
    if (version < 0 || static_cast<std::size_t>(version) > kMigrationCount) {
      throw std::runtime_error("store: database schema version " + std::to_string(version) +
                               " is newer than this build knows (" + std::to_string(kMigrationCount) +
                               "); upgrade granulab");
    }
    if (static_cast<std::size_t>(version) == kMigrationCount) return;  // nothing to do: the guard rolls back
    db.exec(kMigrations[version]);
    db.exec("PRAGMA user_version = " + std::to_string(version + 1));
    tx.commit();
  }
}

}  // namespace granulab::server
