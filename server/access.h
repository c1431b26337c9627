// Who may do what (docs/api.md, "Users"): the caller of a request by its bearer token, the gate that
// answers 401 before any route, and the owner checks of the routes that read or change one job or sweep.
#pragma once

#include <map>
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

/// Reads a token file: one `<user> <token> [admin]` per line; blank lines and lines starting with # are
/// skipped. A token or a user listed twice is an error; `warning` says so when others may read the file.
std::map<std::string, User> read_token_file(const std::string& path, std::string* warning = nullptr);

class Access {
 public:
  /// `tokens` empty: an open server, where everyone is an anonymous admin. `private_reads`: reading a job
  /// or listing jobs is for its owner and admins only.
  Access(std::map<std::string, User> tokens, bool private_reads)
      : tokens_(std::move(tokens)), private_reads_(private_reads) {}

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
  bool needs_tokens() const { return !tokens_.empty(); }
  std::size_t token_count() const { return tokens_.size(); }

 private:
  bool may(const User& who, const std::string& owner, bool write) const {
    return who.admin || owner == who.name || (!write && !private_reads_);
  }
  std::map<std::string, User> tokens_;
  bool private_reads_;
};

}  // namespace granulab::server
