// The HTTP API of docs/api.md on cpp-httplib (the only file that includes it). Handlers parse,
// validate and talk to the store; simulations run on the WorkerPool, never on a handler thread.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "server/connection_loop.h"
#include "server/store/job_store.h"
#include "server/executor.h"


namespace httplib {
struct Request;
struct Response;
class Server;
}  // namespace httplib

namespace granulab::api {
struct Spec;
}  // namespace granulab::api

namespace granulab::server {

class LoopServer;  // cpp-httplib's server fed by the ConnectionLoop (routes.cpp)

/// A token's holder. Admins may act on every job; others on their own (docs/api.md, "Users").
struct User {
  std::string name;
  bool admin = false;
};

struct HttpOptions {
  std::size_t max_body_bytes = 1 << 20;  ///< larger request bodies get 413 (chunked ones too)
  int handler_threads = 8;               ///< threads answering complete requests (never engine workers)
  /// Access tokens (token -> user). When not empty, every route but /v1/health needs
  /// `Authorization: Bearer <token>`, jobs record their owner, and only the owner or an admin may
  /// cancel, delete or re-prioritise a job.
  std::map<std::string, User> tokens;
  bool private_reads = false;            ///< reading a job is for its owner and admins only
  int max_queued_per_user = 1000;        ///< more queued jobs of one user get 429
  int max_jobs_per_sweep = 1000;         ///< a larger sweep is a 400
  /// Per-job budget, checked against the experiment's workload estimate when a job is submitted (400).
  double max_memory_bytes = 0;           ///< peak memory; 0 = half the machine's physical memory
  double max_sphere_steps = 1e13;        ///< spheres x time steps (about 9 h at 3e8 per second)
  /// Timeouts and connection limits (docs/api.md, "Connections").
  int request_timeout_ms = 10000;
  int keep_alive_timeout_ms = 5000;
  int keep_alive_max_requests = 100;
  int max_connections = 512;
  /// The limit for a job's worker (its secret checked before the body is read): checkpoints, snapshots.
  std::size_t max_worker_body_bytes = std::size_t(1) << 30;
};

/// Reads a token file: one `<user> <token> [admin]` per line; blank lines and lines starting with # are
/// skipped. A token or a user listed twice is an error; `warning` says so when others may read the file.
std::map<std::string, User> read_token_file(const std::string& path, std::string* warning = nullptr);

class HttpServer {
 public:
  HttpServer(JobStore& store, Executor& pool, const HttpOptions& options = {});
  ~HttpServer();

  /// Binds to host:port (port 0 = any free port) and returns the port, or -1 on failure.
  int bind(const std::string& host, int port);
  /// Serves until stop() (blocking).
  void serve();
  void stop();

 private:
  void routes();
  /// False (and a 400 naming the limit and the estimate) when the job is over the per-job budget.
  bool within_budget(const api::Spec& spec, httplib::Response& res) const;
  /// Why the job is over the per-job budget (naming the limit and the estimate), or empty.
  std::string budget_problem(const api::Spec& spec) const;
  /// A dry run's answer: spheres, steps, memory and the expected wall time at this server's recent speed.
  nlohmann::json cost_estimate(const api::Spec& spec);
  /// The holder of the request's bearer token; with tokens off, an anonymous admin.
  std::optional<User> caller(const httplib::Request& req) const;
  /// The job of the path's id if `who` may read it (or, `write`, change it); otherwise answers 404/403.
  std::optional<JobRecord> job_for(const httplib::Request& req, httplib::Response& res, const char* action,
                                   bool write);
  /// The same for a sweep.
  std::optional<SweepRecord> sweep_for(const httplib::Request& req, httplib::Response& res, const char* action,
                                       bool write);
  /// The owner a listing is filtered by (?owner=, or the caller on a private server), or nullopt after a 403.
  std::optional<std::string> listing_owner(const httplib::Request& req, httplib::Response& res, const char* what);
  /// False (and a 429 naming the limit) when `who` may not queue `more` jobs.
  bool within_queue_quota(const User& who, std::size_t more, httplib::Response& res);
  /// The route table (cpp-httplib's server, whose type only routes.cpp sees).
  httplib::Server& router();
  void sweep_routes();    // sweep_routes.cpp
  void picture_routes();  // picture_routes.cpp
  void export_routes();   // export_routes.cpp
  void web_routes();      // web_routes.cpp
  void worker_routes();   // worker_routes.cpp
  /// The job of a worker route's path id, if the request carries its worker's secret (else 404/403/409).
  std::optional<JobRecord> worker_job(const httplib::Request& req, httplib::Response& res);
  /// The connection loop's question before reading a large body: is this a job's worker, by its secret?
  bool worker_may_send(const std::string& target, const std::string& token);
  void remember_worker_secret(std::int64_t job, const std::string& secret);
  JobStore& store_;
  Executor& pool_;
  std::mutex worker_secrets_mutex_;
  std::unordered_map<std::int64_t, std::string> worker_secrets_;  ///< job id -> its worker's secret, as seen
  HttpOptions options_;
  std::unique_ptr<LoopServer> http_;
  std::unique_ptr<ConnectionLoop> connections_;
};

}  // namespace granulab::server
