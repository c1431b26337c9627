// The daemon's HTTP side assembled: the access rule, the admission checks, the workers' secrets, the
// route table and the transport. It mounts no route itself: granulabd (main.cpp) mounts the groups of
// server/routes/routes.h, a test the ones it needs.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>

#include "server/access.h"
#include "server/admission.h"
#include "server/executor.h"
#include "server/http/router.h"
#include "server/routes/routes.h"
#include "server/store/job_store.h"
#include "server/worker_secrets.h"

namespace granulab::server {

namespace http {
class Transport;
}

struct HttpOptions {
  std::size_t max_body_bytes = 1 << 20;  ///< B; larger request bodies get 413 (chunked ones too)
  int handler_threads = 8;               ///< threads answering complete requests (never engine workers)
  /// Access tokens (token or its token_hash() -> user). When not empty, every route but /v1/health needs
  /// `Authorization: Bearer <token>`, jobs record their owner, and only the owner or an admin may
  /// cancel, delete or re-prioritise a job.
  std::map<std::string, User> tokens;
  bool private_reads = false;      ///< reading a job is for its owner and admins only
  int max_queued_per_user = 1000;  ///< more queued jobs of one user get 429
  int max_jobs_per_sweep = 1000;   ///< a larger sweep is a 400
  double max_sweep_bytes = 16e6;   ///< B of specs one sweep stores (points x spec size); more is a 400
  /// Per-job budget, checked against the experiment's workload estimate when a job is submitted (400).
  double max_memory_bytes = 0;     ///< B, peak memory; 0 = half the machine's physical memory
  double max_sphere_steps = 4e12;  ///< spheres x time steps (under 12 h at the slowest full-size speed measured, 9.4e7/s)
  double max_user_bytes = 0;       ///< B one user's jobs may hold or be expected to write; 0 = no limit
  /// Timeouts and connection limits (docs/api.md, "Connections").
  int request_timeout_ms = 10000;
  int keep_alive_timeout_ms = 5000;
  int keep_alive_max_requests = 100;
  int max_connections = 512;
  int max_connections_per_peer = 0;  ///< 0: a quarter of max_connections (ConnectionOptions)
  /// B; the limit for a job's worker (its secret checked before the body is read): checkpoints, snapshots.
  std::size_t max_worker_body_bytes = std::size_t(1) << 30;
  /// PEM files of the certificate (chain) and its key: with both, the server speaks HTTPS only.
  std::string tls_cert_file, tls_key_file;
  /// This machine's speed probe for the cost estimates (server/machine_speed.h); none: the table alone.
  const MachineSpeed* machine_speed = nullptr;
};

class HttpServer {
 public:
  HttpServer(JobStore& store, Executor& executor, const HttpOptions& options = {});
  ~HttpServer();

  /// Mounts a route group (before bind).
  void mount(void (*group)(http::Router&, const RouteContext&)) { group(router_, context_); }
  /// The routes mounted so far.
  const http::Router& router() const { return router_; }
  /// Binds to host:port (port 0 = any free port) and returns the port, or -1 on failure.
  int bind(const std::string& host, int port);
  /// Serves until stop() (blocking).
  void serve();
  void stop();
  /// The token file read again (SIGHUP): from the next request on; connections and jobs carry on.
  void replace_tokens(std::map<std::string, User> tokens) { access_.replace_tokens(std::move(tokens)); }

 private:
  Access access_;
  Admission admission_;
  WorkerSecrets worker_secrets_;
  RouteContext context_;
  http::Router router_;
  std::unique_ptr<http::Transport> transport_;
};

}  // namespace granulab::server
