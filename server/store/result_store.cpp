// JobStore: a job's results, its curve (whole, or rows as they come), snapshots and checkpoint (see job_store.h).
#include "server/store/job_store.h"

#include <algorithm>

#include "server/store/job_rows.h"
#include "server/store/sqlite.h"
#include "server/store/store_clock.h"

namespace granulab::server {

using sqlite::Statement;
using sqlite::Transaction;

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

void JobStore::append_results(std::int64_t id, std::size_t first_index, const std::vector<api::StoredRow>& rows,
                              const std::vector<SnapshotBlob>& snapshots, const Checkpoint* checkpoint) {
  std::lock_guard<std::mutex> lock(mutex_);
  Transaction tx(*db_);
  {
    Statement st(*db_, "SELECT 1 FROM jobs WHERE id = ?1 AND status = 'running'");
    st.bind(1, id);
    if (!st.step()) return;
  }
  Statement row(*db_, "INSERT OR REPLACE INTO curve_rows (job_id, idx, line, row_values) VALUES (?1, ?2, ?3, ?4)");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    row.reset();
    row.bind(1, id).bind(2, std::int64_t(first_index + k)).bind(3, rows[k].csv).bind(4, rows[k].values).run();
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
    cp.bind(3, checkpoint->rows)
        .bind(4, checkpoint->snapshots)
        .bind(5, checkpoint->engine_version)
        .bind(6, now_ms())
        .run();
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

std::optional<std::pair<std::string, std::vector<api::StoredRow>>> JobStore::live_rows_locked(std::int64_t id,
                                                                                              bool last_only) {
  Statement header(*db_, "SELECT curve_header FROM jobs WHERE id = ?1");
  header.bind(1, id);
  if (!header.step()) return std::nullopt;
  std::pair<std::string, std::vector<api::StoredRow>> out{header.column_text(0), {}};
  if (out.first.empty()) return std::nullopt;
  Statement rows(*db_, last_only ? "SELECT line, row_values FROM curve_rows WHERE job_id = ?1 ORDER BY idx DESC LIMIT 1"
                                 : "SELECT line, row_values FROM curve_rows WHERE job_id = ?1 ORDER BY idx");
  rows.bind(1, id);
  while (rows.step()) out.second.push_back({rows.column_text(0), rows.column_text(1)});
  return out;
}

std::optional<std::string> JobStore::live_curve_csv(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  {
    Statement whole(*db_, "SELECT csv FROM curves WHERE job_id = ?1");
    whole.bind(1, id);
    if (whole.step()) return whole.column_text(0);
  }
  const auto live = live_rows_locked(id, false);
  if (!live) return std::nullopt;
  std::string csv = live->first;
  for (const api::StoredRow& row : live->second) csv += row.csv;
  return csv;
}

std::optional<std::pair<std::string, api::StoredRow>> JobStore::latest_row(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto live = live_rows_locked(id, true);
  if (!live || live->second.empty()) return std::nullopt;
  return std::make_pair(std::move(live->first), std::move(live->second.front()));
}

std::optional<std::pair<std::string, std::vector<api::StoredRow>>> JobStore::live_rows(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  return live_rows_locked(id, false);
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

}  // namespace granulab::server
