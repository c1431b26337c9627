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
    // The new checkpoint's chunks are all in (put_checkpoint_chunk): it becomes the job's now, and the
    // previous one's chunks garbage (drop_checkpoint_garbage).
    Statement cp(*db_,
                 "INSERT OR REPLACE INTO checkpoints (job_id, generation, chunks, bytes, rows, snapshots, "
                 "engine_version, at_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
    cp.bind(1, id).bind(2, checkpoint->generation).bind(3, checkpoint->chunks).bind(4, checkpoint->bytes);
    cp.bind(5, checkpoint->rows)
        .bind(6, checkpoint->snapshots)
        .bind(7, checkpoint->engine_version)
        .bind(8, now_ms())
        .run();
  }
  tx.commit();
}

std::optional<JobStore::Checkpoint> JobStore::checkpoint(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st(*db_,
               "SELECT generation, chunks, bytes, rows, snapshots, engine_version FROM checkpoints WHERE job_id = ?1");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  return Checkpoint{st.column_int64(0), st.column_int64(1), st.column_int64(2),
                    st.column_int64(3), st.column_int64(4), st.column_text(5)};
}

std::int64_t JobStore::begin_checkpoint(std::int64_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Above every generation the job has or had (garbage not yet removed included): a new one never mixes
  // with chunks of another.
  Statement st(*db_,
               "SELECT max(coalesce((SELECT max(generation) FROM checkpoint_chunks WHERE job_id = ?1), 0), "
               "coalesce((SELECT generation FROM checkpoints WHERE job_id = ?1), 0))");
  st.bind(1, id);
  std::int64_t generation = st.step() ? st.column_int64(0) + 1 : 1;
  // A job has one run, so one write at a time: an earlier one of it was abandoned (its chunks garbage).
  for (auto w = checkpoint_writes_.begin(); w != checkpoint_writes_.end();)
    if (w->first == id) {
      generation = std::max(generation, w->second + 1);
      w = checkpoint_writes_.erase(w);
    } else {
      ++w;
    }
  checkpoint_writes_.insert({id, generation});
  return generation;
}

bool JobStore::put_checkpoint_chunk(std::int64_t id, std::int64_t generation, std::int64_t index, const char* data,
                                    std::size_t size) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!checkpoint_writes_.count({id, generation})) return false;  // never the stored checkpoint's chunks
  Statement st(*db_,
               "INSERT OR REPLACE INTO checkpoint_chunks (job_id, generation, idx, data) VALUES (?1, ?2, ?3, ?4)");
  st.bind(1, id).bind(2, generation).bind(3, index).bind_blob_in_place(4, data, size).run();
  return true;
}

void JobStore::end_checkpoint_write(std::int64_t id, std::int64_t generation) {
  std::lock_guard<std::mutex> lock(mutex_);
  checkpoint_writes_.erase({id, generation});
}

std::optional<std::string> JobStore::checkpoint_chunk(std::int64_t id, std::int64_t generation, std::int64_t index) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Only the job's stored checkpoint, or the one being written (checked whole before it is committed), is
  // read: a torn write's or a superseded one's chunks, garbage until dropped, are never a resume point.
  const bool under_way = checkpoint_writes_.count({id, generation}) > 0;
  Statement st(*db_, under_way ? "SELECT data FROM checkpoint_chunks WHERE job_id = ?1 AND generation = ?2 AND idx = ?3"
                               : "SELECT c.data FROM checkpoint_chunks c JOIN checkpoints k ON k.job_id = c.job_id AND "
                                 "k.generation = c.generation WHERE c.job_id = ?1 AND c.generation = ?2 AND c.idx = ?3");
  st.bind(1, id).bind(2, generation).bind(3, index);
  if (!st.step()) return std::nullopt;
  return st.column_blob_string(0);
}

std::size_t JobStore::drop_checkpoint_garbage(std::size_t max_chunks) {
  std::size_t dropped = 0;
  while (dropped < max_chunks) {
    std::lock_guard<std::mutex> lock(mutex_);
    // One chunk of no checkpoint and of no write under way, per transaction: each holds the store for
    // one chunk's pages at most.
    Statement st(*db_,
                 "SELECT c.rowid, c.job_id, c.generation FROM checkpoint_chunks c LEFT JOIN checkpoints k "
                 "ON k.job_id = c.job_id AND k.generation = c.generation WHERE k.job_id IS NULL");
    std::int64_t rowid = -1;
    while (st.step())
      if (!checkpoint_writes_.count({st.column_int64(1), st.column_int64(2)})) {
        rowid = st.column_int64(0);
        break;
      }
    st.reset();
    if (rowid < 0) break;
    Statement drop(*db_, "DELETE FROM checkpoint_chunks WHERE rowid = ?1");
    drop.bind(1, rowid).run();
    ++dropped;
  }
  return dropped;
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
