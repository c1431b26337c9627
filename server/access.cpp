#include "server/access.h"

#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <sys/stat.h>

#include "server/http/replies.h"

namespace granulab::server {

using http::error;
using http::path_id;

std::map<std::string, User> read_token_file(const std::string& path, std::string* warning) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read token file '" + path + "'");
  struct stat info {};
  if (warning && ::stat(path.c_str(), &info) == 0 && (info.st_mode & (S_IRGRP | S_IROTH)))
    *warning = "token file '" + path + "' is readable by other users of this machine (chmod 600 it)";
  std::map<std::string, User> tokens;
  std::set<std::string> users;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    std::string user, token, role, extra;
    if (!(fields >> user) || user[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (!(fields >> token) || ((fields >> role) && role != "admin") || (fields >> extra))
      throw std::invalid_argument(where + "expected '<user> <token> [admin]'");
    // One token names one user: a shared token would make two people one owner.
    if (tokens.count(token))
      throw std::invalid_argument(where + "this token is already given to '" + tokens[token].name + "'");
    if (!users.insert(user).second) throw std::invalid_argument(where + "user '" + user + "' already has a token");
    tokens[token] = User{user, role == "admin"};
  }
  if (tokens.empty()) throw std::invalid_argument("token file '" + path + "' holds no token");
  return tokens;
}

std::optional<User> Access::caller(const http::Request& req) const {
  if (tokens_.empty()) return User{"", true};  // an open server: everyone may do everything
  const std::string authorization = req.get_header_value("Authorization"), prefix = "Bearer ";
  if (authorization.rfind(prefix, 0) != 0) return std::nullopt;
  const auto it = tokens_.find(authorization.substr(prefix.size()));
  if (it == tokens_.end()) return std::nullopt;
  return it->second;
}

bool Access::gate(const http::Request& req, http::Response& res) const {
  const bool open = req.path == "/v1/health" || req.path == "/" || req.path.rfind("/web/", 0) == 0 ||
                    req.path.rfind("/v1/worker/", 0) == 0;
  if (open || caller(req)) return false;
  error(res, 401, "unauthorized",
        req.has_header("Authorization") ? "unknown access token" : "this server needs 'Authorization: Bearer <token>'");
  return true;
}

namespace {

// The record of the path's id (a job's or a sweep's) if the caller may read it (or, `write`, change it);
// otherwise a 404 or a 403 naming the `action`.
template <class Record, class Get, class May>
std::optional<Record> owned(const char* what, Get get, May may, const http::Request& req, http::Response& res,
                            const char* action) {
  const auto id = path_id(req.matches.at(1));
  std::optional<Record> record = id ? get(*id) : std::nullopt;
  if (!record) {
    error(res, 404, "not_found", std::string("no ") + what + " " + req.matches[1]);
    return std::nullopt;
  }
  if (may(record->owner)) return record;
  error(res, 403, "forbidden",
        std::string(what) + " " + std::to_string(record->id) + " belongs to '" + record->owner +
            "': only its owner or an admin may " + action + " it");
  return std::nullopt;
}

}  // namespace

std::optional<JobRecord> Access::job_for(JobStore& store, const http::Request& req, http::Response& res,
                                         const char* action, bool write) const {
  return owned<JobRecord>(
      "job", [&](std::int64_t id) { return store.get(id); },
      [&](const std::string& owner) { return may(who(req), owner, write); }, req, res, action);
}

std::optional<SweepRecord> Access::sweep_for(JobStore& store, const http::Request& req, http::Response& res,
                                             const char* action, bool write) const {
  return owned<SweepRecord>(
      "sweep", [&](std::int64_t id) { return store.get_sweep(id); },
      [&](const std::string& owner) { return may(who(req), owner, write); }, req, res, action);
}

std::optional<std::string> Access::listing_owner(const http::Request& req, http::Response& res,
                                                 const char* what) const {
  std::string owner = req.has_param("owner") ? req.get_param_value("owner") : "";
  const User me = who(req);
  if (private_reads_ && !me.admin) {
    if (!owner.empty() && owner != me.name) {
      error(res, 403, "forbidden", std::string("this server is private: you may list only your own ") + what, "owner");
      return std::nullopt;
    }
    owner = me.name;
  }
  return owner;
}

}  // namespace granulab::server
