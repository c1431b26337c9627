// The HTTP transport: listens, hands sockets to the ConnectionLoop, parses each complete request into an
// http::Request for the Router and writes its Response back. Everything that depends on the HTTP library
// (cpp-httplib) is in httplib_adapter.cpp, the only file that includes it; the Slurm REST client's
// HttpClient (client.h) is there too.
#pragma once

#include <memory>
#include <string>

#include "server/connection_loop.h"
#include "server/http/router.h"

namespace granulab::server::http {

class Transport {
 public:
  /// Serves `router` (which must outlive the transport and not change once serving starts) with the
  /// connection loop's limits and timeouts.
  Transport(const Router& router, const ConnectionOptions& options);
  ~Transport();
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;

  /// Binds to host:port (port 0 = any free port) and returns the port, or -1 on failure.
  int bind(const std::string& host, int port);
  /// Serves until stop() (blocking); then answers what was already read and closes the rest.
  void serve();
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granulab::server::http
