// Who may do what (docs/api.md, "Users"): the caller of a request by its bearer token, the gate that
// answers 401 before any route, and the owner checks of the routes that read or change one job or sweep.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "server/http/message.h"
#include "server/store/job_store.h"

namespace granulab::server {

/// A token's holder. Admins may act on every job; others on their own.
struct User {
  std::string name;
  bool admin = false;
};

/// How a token is kept: "sha256:" and the hex SHA-256 of its bytes. A token file, a backup of it or a
/// glance over a shoulder does not give the token; the server compares hashes.
std::string token_hash(const std::string& token);

/// Reads a token file: one `<user> <token-or-hash> [admin]` per line (`granulabd token add` writes hashes;
/// a plain token is hashed as it is read); blank lines and lines starting with # are skipped. A token or a
/// user listed twice is an error; `warning` says so when others may read the file. The map is by hash.
std::map<std::string, User> read_token_file(const std::string& path, std::string* warning = nullptr);

/// Appends a new user with a fresh random token (32 bytes from OpenSSL, as 64 hex digits) to the token file,
/// as its hash, creating the file readable by its owner only; returns the token (shown once, kept nowhere).
/// std::invalid_argument for a bad user name or one the file already has.
std::string add_token(const std::string& path, const std::string& user, bool admin);

/// Takes `user`'s line out of the token file (a daemon reading it again on SIGHUP no longer lets the token in);
/// every other line, comments and blank ones included, stays as it was. The file is written anew beside the old
/// one (0600) and renamed over it, so a reader sees the old file or the new one, never half of one.
/// std::invalid_argument for a file that does not read, a user it does not have, or its last user (a file of
/// no token is refused at start and on SIGHUP: the daemon would keep the old tokens).
void remove_token(const std::string& path, const std::string& user);

class Access {
 public:
  /// `tokens` empty: an open server, where everyone is an anonymous admin. `private_reads`: reading a job
  /// or listing jobs is for its owner and admins only.
  /// `tokens` by token or by token_hash() (the token file's).
  Access(std::map<std::string, User> tokens, bool private_reads);

  /// A token file read again (SIGHUP): requests from now on see the new tokens; none in flight fails.
  void replace_tokens(std::map<std::string, User> tokens);

  /// The holder of the request's bearer token; with tokens off, an anonymous admin; nullopt for none.
  std::optional<User> caller(const http::Request& req) const;
  /// The caller, once the gate has let the request through (an anonymous non-admin otherwise).
  User who(const http::Request& req) const { return caller(req).value_or(User{}); }
  /// Before any route: with tokens, a 401 for a request without a known one, except on the routes that are
  /// open (health for monitors, the page, which asks for the token itself, and the workers' routes, which
  /// check their job's own secret). True when it answered.
  bool gate(const http::Request& req, http::Response& res) const;
  /// The job of the path's id (matches[1]) if the caller may read it (or, `write`, change it); otherwise
  /// answers 404 or 403 naming the `action`.
  std::optional<JobRecord> job_for(JobStore& store, const http::Request& req, http::Response& res, const char* action,
                                   bool write) const;
  /// The same for a sweep.
  std::optional<SweepRecord> sweep_for(JobStore& store, const http::Request& req, http::Response& res,
                                       const char* action, bool write) const;
  /// The owner a listing is filtered by (?owner=, or the caller on a private server), or nullopt after a 403.
  std::optional<std::string> listing_owner(const http::Request& req, http::Response& res, const char* what) const;
  /// False (and a 403 naming the field) when `who` asks for a priority above the default 0: jumping the
  /// queue is for admins (everyone on an open server); lowering one's own jobs is for all.
  bool may_use_priority(const User& who, long priority, http::Response& res, const char* field) const;
  /// Whose succeeded jobs `who` may be handed for ?reuse=true: anyone's where reads are open, else its own.
  std::optional<std::string> reuse_owner(const User& who) const {
    if (who.admin || !private_reads_) return std::nullopt;
    return who.name;
  }
  bool needs_tokens() const { return !tokens()->empty(); }
  std::size_t token_count() const { return tokens()->size(); }

 private:
  bool may(const User& who, const std::string& owner, bool write) const {
    return who.admin || owner == who.name || (!write && !private_reads_);
  }
  using TokenMap = std::map<std::string, User>;  ///< token_hash() -> holder
  std::shared_ptr<const TokenMap> tokens() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return tokens_;
  }
  mutable std::mutex mutex_;
  std::shared_ptr<const TokenMap> tokens_;
  bool private_reads_;
};

}  // namespace granulab::server
