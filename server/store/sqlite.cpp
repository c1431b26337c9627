// RAII wrappers over the SQLite C API (see sqlite.h).
#include "server/store/sqlite.h"

#include <stdexcept>

#include <sqlite3.h>

namespace granulab::server::sqlite {

namespace {
constexpr int kBusyTimeoutMs = 5000;
}  // namespace

// ---------------------------------------------------------------------------------------------- Database

Database::Database(const std::string& path) : path_(path) {
  const int rc = sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);  // a handle is returned even on failure (null is a no-op)
    db_ = nullptr;
    throw std::runtime_error("sqlite: cannot open '" + path + "': " + message);
  }
  try {
    sqlite3_extended_result_codes(db_, 1);
    if (sqlite3_busy_timeout(db_, kBusyTimeoutMs) != SQLITE_OK) throw_error("busy_timeout");
    {
      // Answers the mode now in effect: "wal" for a file, "memory" for ":memory:".
      Statement journal(*this, "PRAGMA journal_mode = WAL");
      while (journal.step()) {}
    }
    exec("PRAGMA foreign_keys = ON");
    Statement check(*this, "PRAGMA foreign_keys");
    if (!check.step() || check.column_int64(0) != 1) {
      throw std::runtime_error("sqlite: foreign keys are not supported by this SQLite build");
    }
  } catch (...) {
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw;
  }
}

Database::~Database() {
  // close_v2 never fails on a busy connection: it defers the close until the last statement ends.
  sqlite3_close_v2(db_);
}

void Database::exec(const std::string& sql) {
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    std::string text = message ? message : sqlite3_errstr(rc);
    sqlite3_free(message);
    if ((rc & 0xff) == SQLITE_FULL) throw StoreFull("sqlite: " + text);
    throw Error("sqlite: " + text, sql.substr(0, 200));
  }
}

std::int64_t Database::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_); }

int Database::changes() const { return sqlite3_changes(db_); }

bool Database::autocommit() const { return sqlite3_get_autocommit(db_) != 0; }

void Database::throw_error(const std::string& context, const std::string& sql) const {
  throw Error("sqlite: " + context + ": " + sqlite3_errmsg(db_), sql.substr(0, 200));
}

// --------------------------------------------------------------------------------------------- Statement

Statement::Statement(Database& db, const std::string& sql) : db_(db), sql_(sql) {
  const int rc = sqlite3_prepare_v2(db.handle(), sql.c_str(), static_cast<int>(sql.size() + 1), &stmt_, nullptr);
  if (rc != SQLITE_OK) {
    sqlite3_finalize(stmt_);
    stmt_ = nullptr;
    db_.throw_error("prepare", sql);
  }
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

void Statement::check_bind(int rc, int index) {
  if (rc != SQLITE_OK) db_.throw_error("bind ?" + std::to_string(index), sql_);
}

Statement& Statement::bind(int index, std::int64_t value) {
  check_bind(sqlite3_bind_int64(stmt_, index, value), index);
  return *this;
}

Statement& Statement::bind(int index, double value) {
  check_bind(sqlite3_bind_double(stmt_, index, value), index);
  return *this;
}

Statement& Statement::bind(int index, const std::string& value) {
  check_bind(sqlite3_bind_text64(stmt_, index, value.data(), value.size(), SQLITE_TRANSIENT, SQLITE_UTF8), index);
  return *this;
}

Statement& Statement::bind_blob(int index, const std::vector<std::uint8_t>& value) {
  // sqlite3_bind_blob with a null pointer would bind NULL, so an empty blob is bound explicitly.
  const int rc = value.empty() ? sqlite3_bind_zeroblob(stmt_, index, 0)
                               : sqlite3_bind_blob64(stmt_, index, value.data(), value.size(), SQLITE_TRANSIENT);
  check_bind(rc, index);
  return *this;
}

Statement& Statement::bind_blob_in_place(int index, const void* data, std::size_t size) {
  const int rc = size == 0 ? sqlite3_bind_zeroblob(stmt_, index, 0)
                           : sqlite3_bind_blob64(stmt_, index, data, size, SQLITE_STATIC);
  check_bind(rc, index);
  return *this;
}

Statement& Statement::bind_null(int index) {
  check_bind(sqlite3_bind_null(stmt_, index), index);
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  // The message must be read before reset(), which would replace it.
  const std::string message = std::string("sqlite: ") + sqlite3_errmsg(db_.handle());
  sqlite3_reset(stmt_);
  if ((rc & 0xff) == SQLITE_FULL) throw StoreFull(std::string("sqlite: ") + sqlite3_errstr(rc));
  throw Error(message, sql_.substr(0, 200));
}

void Statement::run() {
  while (step()) {}
}

void Statement::reset() { sqlite3_reset(stmt_); }

bool Statement::is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }

std::int64_t Statement::column_int64(int column) const { return sqlite3_column_int64(stmt_, column); }

double Statement::column_double(int column) const { return sqlite3_column_double(stmt_, column); }

std::string Statement::column_text(int column) const {
  // Pointer first, then the size (the documented order: the size call may not convert the value).
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
  const int bytes = sqlite3_column_bytes(stmt_, column);
  return text ? std::string(text, static_cast<std::size_t>(bytes)) : std::string();
}

std::vector<std::uint8_t> Statement::column_blob(int column) const {
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, column));
  const int bytes = sqlite3_column_bytes(stmt_, column);
  return data ? std::vector<std::uint8_t>(data, data + bytes) : std::vector<std::uint8_t>();
}

std::string Statement::column_blob_string(int column) const {
  const auto* data = static_cast<const char*>(sqlite3_column_blob(stmt_, column));
  const int bytes = sqlite3_column_bytes(stmt_, column);
  return data ? std::string(data, static_cast<std::size_t>(bytes)) : std::string();
}

// ------------------------------------------------------------------------------------------- Transaction

Transaction::Transaction(Database& db) : db_(db) { db_.exec("BEGIN IMMEDIATE"); }

Transaction::~Transaction() {
  if (committed_) return;
  // SQLite may already have rolled back by itself (e.g. after SQLITE_FULL): then there is nothing to undo.
  if (!db_.autocommit()) sqlite3_exec(db_.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
}

void Transaction::commit() {
  db_.exec("COMMIT");  // on failure the transaction stays open and the destructor rolls it back
  committed_ = true;
}

}  // namespace granulab::server::sqlite
