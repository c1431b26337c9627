// The HTTP API of docs/api.md on cpp-httplib (the only file that includes it). Handlers parse,
// validate and talk to the store; simulations run on the WorkerPool, never on a handler thread.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>

#include "server/store/job_store.h"
#include "server/worker_pool.h"

namespace httplib {
class Server;
}

namespace granulab::server {

struct HttpOptions {
  std::size_t max_body_bytes = 1 << 20;  ///< larger request bodies get 413
  int handler_threads = 8;
  /// Access tokens (token -> user). When not empty, every route but /v1/health needs
  /// `Authorization: Bearer <token>`, and jobs record their owner.
  std::map<std::string, std::string> tokens;
};

/// Reads a token file: one `<user> <token>` per line; blank lines and lines starting with # are skipped.
std::map<std::string, std::string> read_token_file(const std::string& path);

class HttpServer {
 public:
  HttpServer(JobStore& store, WorkerPool& pool, const HttpOptions& options = {});
  ~HttpServer();

  /// Binds to host:port (port 0 = any free port) and returns the port, or -1 on failure.
  int bind(const std::string& host, int port);
  /// Serves until stop() (blocking).
  void serve();
  void stop();

 private:
  void routes();
  /// The user of the request's bearer token; "" when tokens are off.
  std::string user_of(const std::string& authorization) const;
  JobStore& store_;
  WorkerPool& pool_;
  HttpOptions options_;
  std::unique_ptr<httplib::Server> http_;
};

}  // namespace granulab::server
