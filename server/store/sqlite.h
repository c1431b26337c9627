// Thin RAII wrappers over the SQLite C API, for the job store only (docs/architecture.md: only server/store
// includes sqlite3). Database owns one connection, Statement one prepared statement, Transaction one
// BEGIN IMMEDIATE ... COMMIT that rolls back in its destructor unless committed, so an exception
// thrown midway never leaves half a state change behind. Every SQLite error becomes a
// std::runtime_error carrying SQLite's own message. None of these classes is thread-safe: the owner
// (JobStore) serialises access to its connection.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace granulab::server::sqlite {

/// An SQLite error: what() is SQLite's message and what was being done, which users may read (a 500's
/// message, a failed job's reason); the statement is kept apart, for logs, since SQL is no user's business.
struct Error : std::runtime_error {
  Error(const std::string& message, std::string statement) : std::runtime_error(message), sql(std::move(statement)) {}
  std::string sql;  ///< the statement that failed (the first 200 characters)
};

/// The database cannot grow: the disk is full, or the file reached the size it may have
/// (JobStore's max_bytes). Writes fail with this, so callers can say so instead of "internal error".
struct StoreFull : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Database {
 public:
  /// Opens (creating if needed) the database at `path`; ":memory:" gives a private in-memory database.
  /// Sets journal_mode=WAL (in-memory databases keep their "memory" journal), foreign_keys=ON and a
  /// busy timeout of 5000 ms.
  explicit Database(const std::string& path);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  /// Runs one or more SQL statements that return no rows of interest (schema, pragmas).
  void exec(const std::string& sql);
  /// The rowid of the last successful INSERT on this connection.
  std::int64_t last_insert_rowid() const;
  /// Rows changed by the last INSERT, UPDATE or DELETE on this connection.
  int changes() const;
  /// True outside any explicit transaction.
  bool autocommit() const;
  /// Throws Error("sqlite: <context>: <SQLite's message for the last error>", sql).
  [[noreturn]] void throw_error(const std::string& context, const std::string& sql = "") const;

  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  sqlite3* db_ = nullptr;
  std::string path_;
};

/// One prepared statement. Parameters are 1-based (as in SQL's ?1), columns 0-based (as in SQLite).
/// Bound text and blobs are copied (SQLITE_TRANSIENT), so temporaries may be bound safely.
class Statement {
 public:
  Statement(Database& db, const std::string& sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int index, std::int64_t value);
  Statement& bind(int index, int value) { return bind(index, static_cast<std::int64_t>(value)); }
  Statement& bind(int index, double value);
  Statement& bind(int index, const std::string& value);
  Statement& bind(int index, const char* value) { return bind(index, std::string(value)); }
  /// Binds a BLOB (an empty vector binds a zero-length blob, not NULL).
  Statement& bind_blob(int index, const std::vector<std::uint8_t>& value);
  /// Binds `size` bytes at `data` as a BLOB without copying them (a checkpoint's chunk): they must stay
  /// as they are until the statement has run.
  Statement& bind_blob_in_place(int index, const void* data, std::size_t size);
  Statement& bind_null(int index);

  /// Advances one row: true if a row is available, false when done; throws on error.
  bool step();
  /// Steps to completion, for statements that return no rows.
  void run();
  /// Rewinds for another execution; bindings are kept.
  void reset();

  bool is_null(int column) const;
  std::int64_t column_int64(int column) const;
  int column_int(int column) const { return static_cast<int>(column_int64(column)); }
  double column_double(int column) const;
  /// Text of the column (empty for NULL); embedded NUL bytes are kept.
  std::string column_text(int column) const;
  /// Bytes of the column (empty for NULL or a zero-length blob).
  std::vector<std::uint8_t> column_blob(int column) const;
  /// The same bytes as a string.
  std::string column_blob_string(int column) const;

 private:
  void check_bind(int rc, int index);

  Database& db_;
  sqlite3_stmt* stmt_ = nullptr;
  std::string sql_;
};

/// BEGIN IMMEDIATE on construction (takes the write lock up front, so two writers never deadlock
/// upgrading a read lock); ROLLBACK on destruction unless commit() succeeded.
class Transaction {
 public:
  explicit Transaction(Database& db);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  void commit();

 private:
  Database& db_;
  bool committed_ = false;
};

}  // namespace granulab::server::sqlite
