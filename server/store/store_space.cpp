// JobStore: how much room the store has left, and the reserve that lets a full store still record why a
// job failed (see job_store.h, Space and release_reserve).
#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <vector>

#include "server/store/job_store.h"
#include "server/store/sqlite.h"

namespace granulab::server {

namespace {

// B. Deleting it frees enough of a full disk for a few small transactions (a job's failure, a cancel) in
// the write-ahead log; 8 MB is hundreds of them.
constexpr std::size_t kReserveBytes = 8u << 20;

double file_bytes(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? 0.0 : double(size);
}

}  // namespace

void JobStore::make_reserve() {
  const std::string& db = db_->path();
  if (db.empty() || db == ":memory:" || !reserve_path_.empty()) return;
  const std::string path = db + "-reserve";
  if (file_bytes(path) >= kReserveBytes) {
    reserve_path_ = path;
    return;
  }
  // Only when the disk keeps room beside it: the reserve must never be what fills it.
  struct statvfs disk {};
  const std::string folder = std::filesystem::path(db).has_parent_path()
                                 ? std::filesystem::path(db).parent_path().string()
                                 : std::string(".");
  if (::statvfs(folder.c_str(), &disk) != 0 || double(disk.f_bavail) * double(disk.f_frsize) < 4.0 * kReserveBytes)
    return;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) return;
  const std::vector<char> zeros(1 << 16, 0);
  bool ok = true;
  for (std::size_t written = 0; ok && written < kReserveBytes; written += zeros.size())
    ok = ::write(fd, zeros.data(), zeros.size()) == ssize_t(zeros.size());
  ok = ::fsync(fd) == 0 && ok;
  ::close(fd);
  if (ok) reserve_path_ = path;
  else ::unlink(path.c_str());
}

bool JobStore::release_reserve() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (reserve_path_.empty()) return false;
  const bool removed = ::unlink(reserve_path_.c_str()) == 0;
  reserve_path_.clear();
  return removed;
}

double JobStore::user_bytes(const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  sqlite::Statement st(*db_, "SELECT coalesce(sum(expected_bytes), 0) FROM jobs WHERE owner = ?1");
  st.bind(1, owner);
  return st.step() ? st.column_double(0) : 0.0;
}

void JobStore::settle_stored_bytes_locked(std::int64_t id) {
  // length() of a blob reads its size from the record, not its pages; the texts are one job's, read once.
  sqlite::Statement st(*db_,
                       "UPDATE jobs SET expected_bytes = length(spec_json) + length(summary_json) + "
                       "coalesce((SELECT sum(length(data)) FROM snapshots WHERE job_id = ?1), 0) + "
                       "coalesce((SELECT length(csv) + length(json) FROM curves WHERE job_id = ?1), 0) + "
                       "coalesce((SELECT sum(length(line) + length(row_values)) FROM curve_rows WHERE job_id = ?1), 0) "
                       "WHERE id = ?1");
  st.bind(1, id).run();
}

JobStore::Space JobStore::space() {
  std::lock_guard<std::mutex> lock(mutex_);
  Space s;
  const auto pragma = [&](const char* name) {
    sqlite::Statement st(*db_, std::string("PRAGMA ") + name);
    return st.step() ? double(st.column_int64(0)) : 0.0;
  };
  const double page = pragma("page_size"), pages = pragma("page_count"), free_pages = pragma("freelist_count");
  {
    sqlite::Statement st(*db_,
                         "SELECT coalesce(sum(expected_bytes), 0) FROM jobs WHERE status IN ('queued', 'running')");
    s.committed = st.step() ? st.column_double(0) : 0.0;
  }
  const std::string& db = db_->path();
  if (db.empty() || db == ":memory:") return s;
  const double wal = file_bytes(db + "-wal");
  s.used = (pages - free_pages) * page + wal;
  s.limited = true;
  // The file may grow to max_page_count pages; the log is not bounded by it but takes the same disk, so it
  // counts against --max-db-mb too.
  double room = std::numeric_limits<double>::infinity();
  if (max_bytes_ > 0) room = double(max_bytes_) - s.used;
  struct statvfs disk {};
  const std::string folder = std::filesystem::path(db).has_parent_path()
                                 ? std::filesystem::path(db).parent_path().string()
                                 : std::string(".");
  if (::statvfs(folder.c_str(), &disk) == 0)
    room = std::min(room, double(disk.f_bavail) * double(disk.f_frsize) + free_pages * page);
  s.room = std::max(0.0, room);
  return s;
}

}  // namespace granulab::server
