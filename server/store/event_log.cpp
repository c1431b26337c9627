// JobStore: the event log, what happened to each job and to the daemon (see job_store.h).
#include "server/store/job_store.h"

#include <algorithm>

#include "server/store/job_rows.h"
#include "server/store/sqlite.h"
#include "server/store/store_clock.h"

namespace granulab::server {

using sqlite::Statement;
using sqlite::Transaction;

void JobStore::log_event(std::int64_t job_id, const std::string& kind, const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  log_event_locked(job_id, kind, message);
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
