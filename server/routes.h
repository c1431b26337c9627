// The HTTP API of CONTRACT.md on cpp-httplib (the only file that includes it). Handlers parse,
// validate and talk to the store; simulations run on the WorkerPool, never on a handler thread.
#pragma once

#include <cstddef>
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
};

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
  JobStore& store_;
  WorkerPool& pool_;
  HttpOptions options_;
  std::unique_ptr<httplib::Server> http_;
};

}  // namespace granulab::server
