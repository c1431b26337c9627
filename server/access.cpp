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

std::optional<JobRecord> Access::job_for(JobStore& store, const http::Request& req, http::Response& res,
                                         const char* action, bool write) const {
  const auto id = path_id(req.matches.at(1));
  auto job = id ? store.get(*id) : std::nullopt;
  if (!job) {
    error(res, 404, "not_found", "no job " + req.matches[1]);
    return std::nullopt;
  }
  if (may(who(req), job->owner, write)) return job;
  error(res, 403, "forbidden",
        "job " + std::to_string(job->id) + " belongs to '" + job->owner + "': only its owner or an admin may " +
            action + " it");
  return std::nullopt;
}

std::optional<SweepRecord> Access::sweep_for(JobStore& store, const http::Request& req, http::Response& res,
                                             const char* action, bool write) const {
  const auto id = path_id(req.matches.at(1));
  auto sweep = id ? store.get_sweep(*id) : std::nullopt;
  if (!sweep) {
    error(res, 404, "not_found", "no sweep " + req.matches[1]);
    return std::nullopt;
  }
  if (may(who(req), sweep->owner, write)) return sweep;
  error(res, 403, "forbidden",
        "sweep " + std::to_string(sweep->id) + " belongs to '" + sweep->owner + "': only its owner or an admin may " +
            action + " it");
  return std::nullopt;
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
