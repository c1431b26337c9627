#include "server/access.h"

#include <fcntl.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <sys/stat.h>

#include "server/http/replies.h"

namespace granulab::server {

using http::error;
using http::path_id;

namespace {

bool is_hash(const std::string& key) {
  return key.size() == 7 + 64 && key.rfind("sha256:", 0) == 0 &&
         key.find_first_not_of("0123456789abcdef", 7) == std::string::npos;
}

std::map<std::string, User> by_hash(std::map<std::string, User> tokens) {
  std::map<std::string, User> out;
  for (auto& [key, user] : tokens) out[is_hash(key) ? key : token_hash(key)] = std::move(user);
  return out;
}

}  // namespace

std::string token_hash(const std::string& token) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (!EVP_Digest(token.data(), token.size(), digest, &length, EVP_sha256(), nullptr))
    throw std::runtime_error("OpenSSL could not hash a token");
  static const char hex[] = "0123456789abcdef";
  std::string out = "sha256:";
  for (unsigned int i = 0; i < length; ++i) out += hex[digest[i] >> 4], out += hex[digest[i] & 15];
  return out;
}

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
    const std::string key = is_hash(token) ? token : token_hash(token);
    // One token names one user: a shared token would make two people one owner.
    if (tokens.count(key))
      throw std::invalid_argument(where + "this token is already given to '" + tokens[key].name + "'");
    if (!users.insert(user).second) throw std::invalid_argument(where + "user '" + user + "' already has a token");
    tokens[key] = User{user, role == "admin"};
  }
  if (tokens.empty()) throw std::invalid_argument("token file '" + path + "' holds no token");
  return tokens;
}

std::string add_token(const std::string& path, const std::string& user, bool admin) {
  const bool name_ok = !user.empty() && user.size() <= 64 && user[0] != '#' &&
                       std::all_of(user.begin(), user.end(), [](char c) {
                         return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
                                c == '@';
                       });
  if (!name_ok)
    throw std::invalid_argument("user name '" + user +
                                "': 1 to 64 letters, digits and _ - . @, not starting with #");
  if (std::ifstream(path)) {
    std::map<std::string, User> existing;
    try {
      existing = read_token_file(path);
    } catch (const std::invalid_argument& e) {
      // An empty file holds no token yet: adding the first one is fine. Any other problem is the file's.
      if (std::string(e.what()).find("holds no token") == std::string::npos) throw;
    }
    for (const auto& [hash, holder] : existing)
      if (holder.name == user) throw std::invalid_argument("user '" + user + "' already has a token in " + path);
  }
  unsigned char random[32];
  if (RAND_bytes(random, sizeof random) != 1) throw std::runtime_error("OpenSSL could not make a random token");
  static const char hex[] = "0123456789abcdef";
  std::string token;
  for (unsigned char b : random) token += hex[b >> 4], token += hex[b & 15];
  const std::string line = user + " " + token_hash(token) + (admin ? " admin" : "") + "\n";
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
  if (fd < 0) throw std::invalid_argument("cannot write token file '" + path + "': " + std::strerror(errno));
  const bool written = ::write(fd, line.data(), line.size()) == ssize_t(line.size());
  const bool closed = ::fsync(fd) == 0 && ::close(fd) == 0;
  if (!written || !closed) throw std::runtime_error("could not write the token file '" + path + "' whole");
  return token;
}

void remove_token(const std::string& path, const std::string& user) {
  read_token_file(path);  // a file that does not read is the file's problem: not rewritten
  std::ifstream in(path);
  std::string kept, line;
  int removed = 0, others = 0;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string name;
    const bool entry = (fields >> name) && name[0] != '#';
    if (entry && name == user) {
      ++removed;
      continue;
    }
    others += entry;
    kept += line + "\n";
  }
  if (!removed) throw std::invalid_argument("user '" + user + "' has no token in " + path);
  if (!others)
    throw std::invalid_argument("'" + user + "' is the last user in " + path +
                                ": granulabd refuses a token file of no token (at start and on SIGHUP, when it keeps "
                                "the tokens it had); add another user first, or run granulabd without --token-file");
  const std::string fresh = path + ".new";
  const int fd = ::open(fresh.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) throw std::invalid_argument("cannot write '" + fresh + "': " + std::strerror(errno));
  const bool written = ::write(fd, kept.data(), kept.size()) == ssize_t(kept.size());
  const bool closed = ::fsync(fd) == 0 && ::close(fd) == 0;
  if (!written || !closed || std::rename(fresh.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(fresh.c_str());
    throw std::runtime_error("could not write the token file '" + path + "' anew: " + reason);
  }
}

Access::Access(std::map<std::string, User> tokens, bool private_reads)
    : tokens_(std::make_shared<const TokenMap>(by_hash(std::move(tokens)))), private_reads_(private_reads) {}

void Access::replace_tokens(std::map<std::string, User> tokens) {
  auto fresh = std::make_shared<const TokenMap>(by_hash(std::move(tokens)));
  std::lock_guard<std::mutex> lock(mutex_);
  tokens_ = std::move(fresh);
}

std::optional<User> Access::caller(const http::Request& req) const {
  const std::shared_ptr<const TokenMap> tokens = this->tokens();
  if (tokens->empty()) return User{"", true};  // an open server: everyone may do everything
  const std::string authorization = req.get_header_value("Authorization"), prefix = "Bearer ";
  if (authorization.rfind(prefix, 0) != 0) return std::nullopt;
  const auto it = tokens->find(token_hash(authorization.substr(prefix.size())));
  if (it == tokens->end()) return std::nullopt;
  return it->second;
}

bool Access::may_use_priority(const User& who, long priority, http::Response& res, const char* field) const {
  if (priority <= 0 || who.admin) return true;
  error(res, 403, "forbidden",
        "a priority above 0 (the default) is for admins, so that nobody jumps the queue of others; got " +
            std::to_string(priority) + " (0 or below is yours to choose)",
        field);
  return false;
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
