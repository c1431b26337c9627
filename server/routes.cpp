#include "server/routes.h"


#include <algorithm>
#include <atomic>
#include <cstdint>
#include <optional>
#include <chrono>
#include <fstream>
#include <set>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "api/curve_format.h"
#include "api/engine_version.h"
#include "api/runner.h"
#include "api/spec.h"
#include "api/spec_docs.h"
#include "api/sweep.h"
#include "api/bounded_json.h"
#include "server/openapi.h"
#include "server/route_helpers.h"
#include "server/store/sqlite.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

namespace granulab::server {

namespace {

// One complete request, already in memory (the ConnectionLoop read it), as the stream cpp-httplib parses;
// the answer is collected in memory too, and the ConnectionLoop's poll thread sends it as the client reads.
class BufferedStream : public httplib::Stream {
 public:
  BufferedStream(int fd, const std::string& request, std::string& response)
      : fd_(fd), request_(request), response_(response) {}
  bool is_readable() const override { return position_ < request_.size(); }
  bool is_writable() const override { return true; }  // the answer goes to memory; the poll thread sends it
  ssize_t read(char* out, size_t size) override {
    size = std::min(size, request_.size() - position_);
    std::copy_n(request_.data() + position_, size, out);
    position_ += size;
    return ssize_t(size);
  }
  ssize_t write(const char* data, size_t size) override {
    response_.append(data, size);
    return ssize_t(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override { address(::getpeername, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { address(::getsockname, ip, port); }
  socket_t socket() const override { return fd_; }

 private:
  template <typename Query>
  void address(Query query, std::string& ip, int& port) const {
    sockaddr_storage a{};
    socklen_t length = sizeof a;
    ip.clear();
    port = 0;
    if (query(fd_, reinterpret_cast<sockaddr*>(&a), &length) != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (a.ss_family == AF_INET) {
      const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
      ::inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
      port = ntohs(v4->sin_port);
    } else if (a.ss_family == AF_INET6) {
      const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
      ::inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
      port = ntohs(v6->sin6_port);
    }
    ip = text;
  }
  int fd_;
  const std::string& request_;
  std::string& response_;
  std::size_t position_ = 0;
};

}  // namespace

// cpp-httplib's server with its connection handling replaced: accepted sockets go to the ConnectionLoop,
// and complete requests come back to process_request (parsing, routing, writing the response).
class LoopServer : public httplib::Server {
 public:
  ConnectionLoop* loop = nullptr;
  /// cpp-httplib listens with a backlog of 5: a burst of connections beyond it waited seconds for the
  /// kernel's SYN-ACK retries. Listening again on the bound socket raises it (Linux keeps the socket).
  void raise_backlog() { ::listen(svr_sock_, SOMAXCONN); }
  bool answer(int fd, const std::string& request, bool last, std::string& response) {
    BufferedStream stream(fd, request, response);
    bool closed = false;
    const bool ok = process_request(stream, last, closed, [](httplib::Request&) {});
    return ok && !closed;
  }

 private:
  bool process_and_close_socket(socket_t sock) override {
    loop->adopt(sock);
    return true;
  }
};

using nlohmann::json;
using namespace http;

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
    if (tokens.count(token)) throw std::invalid_argument(where + "this token is already given to '" + tokens[token].name + "'");
    if (!users.insert(user).second) throw std::invalid_argument(where + "user '" + user + "' already has a token");
    tokens[token] = User{user, role == "admin"};
  }
  if (tokens.empty()) throw std::invalid_argument("token file '" + path + "' holds no token");
  return tokens;
}

bool HttpServer::within_queue_quota(const User& who, std::size_t more, httplib::Response& res) {
  if (options_.max_queued_per_user <= 0) return true;
  const std::size_t queued = store_.count("queued", who.name);
  if (queued + more <= std::size_t(options_.max_queued_per_user)) return true;
  error(res, 429, "quota",
        (who.name.empty() ? std::string("the server") : "user '" + who.name + "'") + " has " + std::to_string(queued) +
            " queued jobs and asks for " + std::to_string(more) + " more; the limit is " +
            std::to_string(options_.max_queued_per_user) + " (max_queued_per_user): wait for some to start or cancel some");
  return false;
}

std::optional<std::string> HttpServer::listing_owner(const httplib::Request& req, httplib::Response& res,
                                                     const char* what) {
  std::string owner = req.has_param("owner") ? req.get_param_value("owner") : "";
  const User who = caller(req).value_or(User{});
  if (options_.private_reads && !who.admin) {
    if (!owner.empty() && owner != who.name) {
      error(res, 403, "forbidden", std::string("this server is private: you may list only your own ") + what, "owner");
      return std::nullopt;
    }
    owner = who.name;
  }
  return owner;
}

std::optional<SweepRecord> HttpServer::sweep_for(const httplib::Request& req, httplib::Response& res, const char* action,
                                                bool write) {
  const auto id = path_id(req.matches[1]);
  auto sweep = id ? store_.get_sweep(*id) : std::nullopt;
  if (!sweep) {
    error(res, 404, "not_found", "no sweep " + std::string(req.matches[1]));
    return std::nullopt;
  }
  const User who = caller(req).value_or(User{});
  if (who.admin || sweep->owner == who.name || (!write && !options_.private_reads)) return sweep;
  error(res, 403, "forbidden",
        "sweep " + std::to_string(sweep->id) + " belongs to '" + sweep->owner + "': only its owner or an admin may " +
            action + " it");
  return std::nullopt;
}

std::optional<User> HttpServer::caller(const httplib::Request& req) const {
  if (options_.tokens.empty()) return User{"", true};  // an open server: everyone may do everything
  const std::string authorization = req.get_header_value("Authorization"), prefix = "Bearer ";
  if (authorization.rfind(prefix, 0) != 0) return std::nullopt;
  const auto it = options_.tokens.find(authorization.substr(prefix.size()));
  if (it == options_.tokens.end()) return std::nullopt;
  return it->second;
}

std::optional<JobRecord> HttpServer::job_for(const httplib::Request& req, httplib::Response& res, const char* action,
                                            bool write) {
  const auto id = path_id(req.matches[1]);
  auto job = id ? store_.get(*id) : std::nullopt;
  if (!job) {
    error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
    return std::nullopt;
  }
  const User who = caller(req).value_or(User{});  // the pre-routing handler let only known tokens through
  if (who.admin || job->owner == who.name || (!write && !options_.private_reads)) return job;
  error(res, 403, "forbidden",
        "job " + std::to_string(job->id) + " belongs to '" + job->owner + "': only its owner or an admin may " + action +
            " it");
  return std::nullopt;
}

namespace {

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f GB", bytes / 1e9);
  return text;
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

}  // namespace

std::string HttpServer::budget_problem(const api::Spec& spec) const {
  const Workload w = spec.experiment->workload();
  const std::string size = number(w.spheres) + " spheres in " + number(w.grains) + " grains";
  if (w.peak_bytes() > options_.max_memory_bytes)
    return "this job would need about " + gigabytes(w.peak_bytes()) + " of memory (" + size + "); the server's limit is " +
           gigabytes(options_.max_memory_bytes) + " (max_memory)";
  if (w.sphere_steps() > options_.max_sphere_steps)
    return "this job would take about " + number(w.sphere_steps()) + " sphere-steps (" + size + " x " + number(w.steps) +
           " steps); the server's limit is " + number(options_.max_sphere_steps) + " (max_sphere_steps)";
  return "";
}

bool HttpServer::within_budget(const api::Spec& spec, httplib::Response& res) const {
  const std::string problem = budget_problem(spec);
  if (problem.empty()) return true;
  error(res, 400, "over_budget", problem);
  return false;
}

json HttpServer::cost_estimate(const api::Spec& spec) {
  const Workload w = spec.experiment->workload();
  const std::string experiment = spec.normalized["experiment"].get<std::string>();
  // The speed of this server: the median rate of its recent succeeded jobs of the same experiment (of any,
  // failing that); with none, 5e7 sphere-steps per second per thread, what the crystal runs at here.
  // The workload's step count is an upper bound (confinement until converged, at most its step limit):
  // the same jobs also say what fraction of it runs took (their steps over their own estimate).
  // With no similar run, the bound itself: an upper estimate.
  std::vector<double> same, any, used;
  for (const JobRecord& j : store_.list("succeeded", 50, 0, "")) {
    const json summary = json::parse(j.summary_json, nullptr, false);
    if (!summary.is_object() || !summary.contains("sphere_steps_per_second") ||
        !summary["sphere_steps_per_second"].is_number())
      continue;
    const double rate = summary["sphere_steps_per_second"].get<double>();
    if (!(rate > 0)) continue;
    any.push_back(rate);
    if (j.experiment != experiment) continue;
    same.push_back(rate);
    if (summary.contains("steps") && summary["steps"].is_number()) {
      try {
        // Only runs of a similar length: the fraction depends on the loading (a slow rate spends longer
        // compressing, a small crystal converges sooner), so unlike runs would mislead.
        const double bound = api::parse_spec_text(j.spec_json).experiment->workload().steps;
        if (bound > 0.5 * w.steps && bound < 2 * w.steps)
          used.push_back(std::clamp(summary["steps"].get<double>() / bound, 0.01, 1.0));
      } catch (const std::exception&) {
        // a spec this build no longer accepts says nothing about this one
      }
    }
  }
  double fraction = 1;
  if (!used.empty()) {
    std::nth_element(used.begin(), used.begin() + used.size() / 2, used.end());
    fraction = used[used.size() / 2];
  }
  std::vector<double>& rates = same.empty() ? any : same;
  std::string basis = same.empty() ? (any.empty() ? "typical" : "recent jobs of other experiments")
                                   : "recent " + experiment + " jobs";
  double rate = 5e7 * pool_.threads_per_job();
  if (!rates.empty()) {
    std::nth_element(rates.begin(), rates.begin() + rates.size() / 2, rates.end());
    rate = rates[rates.size() / 2];
  }
  json out = {{"dry_run", true},
              {"experiment", experiment},
              {"spheres", w.spheres},
              {"grains", w.grains},
              {"steps", w.steps},
              {"sphere_steps", w.sphere_steps()},
              {"memory_bytes", w.peak_bytes()},
              {"sphere_steps_per_second", rate},
              {"rate_basis", basis},
              {"expected_seconds", fraction * w.sphere_steps() / rate},
              {"steps_fraction", fraction},
              {"queued_ahead", store_.count("queued")},
              {"units", {{"memory_bytes", "B"}, {"expected_seconds", "s"}, {"sphere_steps_per_second", "1/s"}}}};
  if (const std::string problem = budget_problem(spec); !problem.empty()) out["over_budget"] = problem;
  return out;
}

HttpServer::HttpServer(JobStore& store, Executor& pool, const HttpOptions& options)
    : store_(store), pool_(pool), options_(options), http_(std::make_unique<LoopServer>()) {
  if (options_.max_memory_bytes <= 0)
    options_.max_memory_bytes = 0.5 * double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
  ConnectionOptions connection;
  connection.limits.max_body_bytes = options_.max_body_bytes;
  connection.limits.max_trusted_body_bytes = options_.max_worker_body_bytes;
  connection.limits.trusted = [this](const std::string& target, const std::string& token) {
    return worker_may_send(target, token);
  };
  for (const auto& [job, secret] : store_.worker_secrets()) worker_secrets_[job] = secret;  // jobs on a cluster
  connection.handler_threads = options_.handler_threads;
  connection.max_connections = options_.max_connections;
  connection.request_timeout_ms = options_.request_timeout_ms;
  connection.keep_alive_timeout_ms = options_.keep_alive_timeout_ms;
  connection.keep_alive_max_requests = options_.keep_alive_max_requests;
  connections_ = std::make_unique<ConnectionLoop>(
      connection, [this](int fd, const std::string& request, bool last, std::string& response) {
        return http_->answer(fd, request, last, response);
      });
  http_->loop = connections_.get();
  http_->set_payload_max_length(std::max(options_.max_body_bytes, options_.max_worker_body_bytes));  // the loop enforces both
  // The Keep-Alive header cpp-httplib writes states the loop's policy.
  http_->set_keep_alive_max_count(std::size_t(options_.keep_alive_max_requests));
  http_->set_keep_alive_timeout(std::max(1, options_.keep_alive_timeout_ms / 1000));
  // Only SO_REUSEADDR: cpp-httplib's default adds SO_REUSEPORT, which let a second daemon bind the same
  // port and take half the requests.
  http_->set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // Answers go out at once: with Nagle's algorithm a kept-alive connection waited for the client's delayed
  // ACK on every request (26 ms each, 38 requests/s, against 4,000/s on fresh connections).
  http_->set_tcp_nodelay(true);
  // The accept thread only hands sockets to the loop: one task thread is plenty.
  http_->new_task_queue = [] { return new httplib::ThreadPool(1); };
  // Every response carries a request id; one access-log line per request.
  // With tokens, every route but health needs a known bearer token.
  http_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    // The page itself asks for the token; health is for monitors.
    // A job's worker presents that job's own secret instead (worker_routes.cpp).
    const bool open = req.path == "/v1/health" || req.path == "/" || req.path.rfind("/web/", 0) == 0 ||
                      req.path.rfind("/v1/worker/", 0) == 0;
    if (open || caller(req)) return httplib::Server::HandlerResponse::Unhandled;
    error(res, 401, "unauthorized",
          req.has_header("Authorization") ? "unknown access token" : "this server needs 'Authorization: Bearer <token>'");
    return httplib::Server::HandlerResponse::Handled;
  });
  http_->set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
    static std::atomic<std::uint64_t> next{1};
    // A 500 already has its own (the id the log names); headers are a multimap, so never add a second.
    if (!res.has_header("X-Request-Id")) res.set_header("X-Request-Id", std::to_string(next++));
  });
  // Nothing a handler throws reaches the framework or the client: a JSON 500 with the request id, and the
  // exception text only in the daemon's log.
  http_->set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown exception";
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    static std::atomic<std::uint64_t> next_error{1};
    const std::string id = "e" + std::to_string(next_error++);
    bool full = false;
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const sqlite::StoreFull&) {
      full = true;
    } catch (...) {
    }
    spdlog::error("{} {} -> {} ({}): {}", req.method, req.path, full ? 507 : 500, id, what);
    res.set_header("X-Request-Id", id);
    if (full)
      return error(res, 507, "storage_full",
                   "the server's storage is full (its disk, or --max-db-mb): nothing was stored; tell its administrator");
    error(res, 500, "internal", "internal error; the server's log has it under request id " + id);
  });
  http_->set_logger([](const httplib::Request& req, const httplib::Response& res) {
    spdlog::info("{} {} {} -> {} ({} bytes) id={}", req.remote_addr, req.method, req.path, res.status, res.body.size(),
                 res.get_header_value("X-Request-Id"));
  });
  http_->set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    if (res.status == 413) error(res, 413, "too_large", "request body too large");
    else if (res.status == 404) error(res, 404, "not_found", "no such route");
    else if (res.status == 400) error(res, 400, "bad_request", "malformed request");
    else if (res.status == 414) error(res, 414, "uri_too_long", "the request's path and query are longer than 8 KiB");
    else error(res, res.status, "http_error", "request failed with HTTP " + std::to_string(res.status));
  });
  routes();
}

HttpServer::~HttpServer() {
  stop();
  connections_->stop();
}

int HttpServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? http_->bind_to_any_port(host) : (http_->bind_to_port(host, port) ? port : -1);
  if (bound > 0) http_->raise_backlog();
  return bound;
}

void HttpServer::serve() {
  http_->listen_after_bind();
  connections_->stop();  // answers what was already read, closes the rest
}

void HttpServer::stop() {
  if (http_->is_running()) http_->stop();
}

httplib::Server& HttpServer::router() { return *http_; }

void HttpServer::routes() {
  sweep_routes();
  picture_routes();
  export_routes();
  web_routes();
  worker_routes();
  http_->Get("/v1/health", [this](const httplib::Request&, httplib::Response& res) {
    reply(res, 200,
          {{"status", "ok"},
           {"engine_version", api::engine_version()},
           {"queued", store_.count("queued")},
           {"running", store_.count("running")},
           {"workers", pool_.workers()},
           {"threads_per_job", pool_.threads_per_job()},
           {"executor", pool_.name()}});
  });

  // The API described (OpenAPI 3.1): built once, the registry does not change at run time.
  http_->Get("/v1/openapi.json", only({}, [](const httplib::Request&, httplib::Response& res) {
    static const std::string document = openapi_document().dump(1) + "\n";
    res.set_content(document, "application/json");
  }));

  // Every registered experiment: its spec fields (default, range, unit, meaning) and curve columns.
  http_->Get("/v1/experiments", only({}, [](const httplib::Request&, httplib::Response& res) {
    static const json description = api::experiments_json();  // the registry does not change at run time
    reply(res, 200, description);
  }));

  http_->Post("/v1/jobs", only({"reuse", "priority", "dry_run"}, [this](const httplib::Request& req, httplib::Response& res) {
    api::Spec spec;
    try {
      spec = api::parse_spec_text(req.body);
    } catch (const api::SpecError& e) {
      return error(res, 400, e.code, e.what(), e.field);
    }
    long priority = 0;
    if (!query_int(req, res, "priority", -100, 100, priority)) return;
    // A dry run: the spec is valid; what it would cost here, and nothing queued.
    const std::string dry_run = req.has_param("dry_run") ? req.get_param_value("dry_run") : "false";
    if (dry_run != "true" && dry_run != "false")
      return error(res, 400, "invalid_value", "'dry_run' must be true or false, got '" + dry_run + "'", "dry_run");
    if (dry_run == "true") return reply(res, 200, cost_estimate(spec));
    if (!within_budget(spec, res)) return;
    const std::string hash = api::spec_hash(spec.normalized);
    const std::string experiment = spec.normalized["experiment"].get<std::string>();
    const std::string reuse = req.has_param("reuse") ? req.get_param_value("reuse") : "false";
    if (reuse != "true" && reuse != "false")
      return error(res, 400, "invalid_value", "'reuse' must be true or false, got '" + reuse + "'", "reuse");
    if (reuse == "true") {
      if (const auto id = store_.find_succeeded(hash, api::engine_version()))
        return reply(res, 200, {{"id", *id}, {"status", "succeeded"}, {"reused", true}});
    }
    const User who = caller(req).value_or(User{});
    if (!within_queue_quota(who, 1, res)) return;
    const std::int64_t id = store_.submit(spec.normalized.dump(), experiment, spec.label, hash, api::engine_version(),
                                          who.name, int(priority));
    pool_.notify();
    reply(res, 201, {{"id", id}, {"status", "queued"}});
  }));

  http_->Get("/v1/jobs", only({"status", "owner", "limit", "offset"}, [this](const httplib::Request& req, httplib::Response& res) {
    long limit = 50, offset = 0;
    if (!query_int(req, res, "limit", 1, 1000, limit) || !query_int(req, res, "offset", 0, 1L << 40, offset)) return;
    const std::string status = req.has_param("status") ? req.get_param_value("status") : "";
    if (!status.empty() && status != "queued" && status != "running" && status != "succeeded" && status != "failed" &&
        status != "cancelled")
      return error(res, 400, "invalid_value",
                   "'status' must be one of: queued, running, succeeded, failed, cancelled, got '" + status + "'",
                   "status");
    const auto owner = listing_owner(req, res, "jobs");
    if (!owner) return;
    json jobs = json::array();
    for (const JobRecord& j : store_.list(status, int(limit), offset, *owner)) {
      jobs.push_back(job_json(j, false));
      if (j.status == "running")
        if (json latest = latest_values(store_, j); !latest.is_null()) jobs.back()["latest"] = std::move(latest);
    }
    reply(res, 200, {{"jobs", jobs}, {"limit", limit}, {"offset", offset}});
  }));

  http_->Get(R"(/v1/jobs/(\d+))", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = job_for(req, res, "read", false);
    if (!job) return;
    json out = job_json(*job, true);
    if (json latest = latest_values(store_, *job); !latest.is_null()) out["latest"] = std::move(latest);
    reply(res, 200, out);
  }));

  http_->Delete(R"(/v1/jobs/(\d+))", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = job_for(req, res, "delete", true);
    if (!job) return;
    switch (store_.remove(job->id)) {
      case JobStore::WriteResult::done:
        return reply(res, 200, {{"id", job->id}, {"deleted", true}});
      case JobStore::WriteResult::not_found:
        return error(res, 404, "not_found", "no job " + std::to_string(job->id));
      case JobStore::WriteResult::wrong_state:
        return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is " + job->status + ": cancel it first");
    }
  }));

  http_->Post(R"(/v1/jobs/(\d+)/priority)", only({"value"}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = job_for(req, res, "re-prioritise", true);
    if (!job) return;
    long priority = 0;
    if (!req.has_param("value")) return error(res, 400, "missing", "'value' (the new priority, -100 to 100) is required", "value");
    if (!query_int(req, res, "value", -100, 100, priority)) return;
    switch (store_.set_priority(job->id, int(priority))) {
      case JobStore::WriteResult::done:
        return reply(res, 200, {{"id", job->id}, {"priority", priority}});
      case JobStore::WriteResult::not_found:
        return error(res, 404, "not_found", "no job " + std::to_string(job->id));
      case JobStore::WriteResult::wrong_state:
        return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is no longer queued");
    }
  }));

  http_->Post(R"(/v1/jobs/(\d+)/cancel)", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = job_for(req, res, "cancel", true);
    if (!job) return;
    const std::int64_t id = job->id;
    switch (store_.request_cancel(id)) {
      case JobStore::CancelResult::cancelled_queued:
        pool_.cancel_requested(id);  // on a cluster it may be pending there
        return reply(res, 200, {{"id", id}, {"status", "cancelled"}});
      case JobStore::CancelResult::requested_running:
        pool_.cancel_requested(id);
        return reply(res, 202, {{"id", id}, {"status", "running"}, {"cancel_requested", true}});
      case JobStore::CancelResult::not_found:
        return error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
      case JobStore::CancelResult::wrong_state:
        return error(res, 409, "wrong_state", "job " + std::to_string(id) + " has already finished");
    }
  }));

  http_->Get(R"(/v1/jobs/(\d+)/curve)", only({"format"}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = job_for(req, res, "read", false);
    if (!job) return;
    const std::int64_t id = job->id;
    // A finished job's stored curve; a running job's rows so far; what a cancelled or failed one computed.
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "json";
    if (format != "json" && format != "csv")
      return error(res, 400, "invalid_value", "'format' must be json or csv, got '" + format + "'", "format");
    const bool csv = format == "csv";
    if (job->status == "succeeded" && !csv)
      if (const auto json_text = store_.curve_json(id)) return res.set_content(*json_text, "application/json");
    const auto text = store_.live_curve_csv(id);
    if (!text)
      return error(res, 409, "wrong_state", "job " + std::to_string(id) + " is " + job->status + " and has no curve yet");
    if (csv) return res.set_content(*text, "text/csv");
    res.set_content(api::curve_csv_to_json(*text).dump(), "application/json");
  }));

  http_->Get(R"(/v1/jobs/(\d+)/snapshots)", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = job_for(req, res, "read", false);
    if (!job) return;
    const std::int64_t id = job->id;
    json list = json::array();
    for (const auto& s : store_.snapshots(id)) list.push_back({{"index", s.index}, {"strain", s.strain}, {"bytes", s.bytes}});
    reply(res, 200, {{"snapshots", list}});
  }));
}

}  // namespace granulab::server
