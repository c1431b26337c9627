#include "server/http_server.h"

#include "server/http/transport.h"

namespace granulab::server {

namespace {

ConnectionOptions connection_options(const HttpOptions& o, WorkerSecrets& secrets) {
  ConnectionOptions connection;
  connection.limits.max_body_bytes = o.max_body_bytes;
  connection.limits.max_trusted_body_bytes = o.max_worker_body_bytes;
  connection.limits.trusted = [&secrets](const std::string& target, const std::string& token) {
    return secrets.may_send(target, token);
  };
  connection.handler_threads = o.handler_threads;
  connection.max_connections = o.max_connections;
  connection.max_connections_per_peer = o.max_connections_per_peer;
  connection.request_timeout_ms = o.request_timeout_ms;
  connection.keep_alive_timeout_ms = o.keep_alive_timeout_ms;
  connection.keep_alive_max_requests = o.keep_alive_max_requests;
  connection.tls_cert_file = o.tls_cert_file;
  connection.tls_key_file = o.tls_key_file;
  return connection;
}

}  // namespace

HttpServer::HttpServer(JobStore& store, Executor& executor, const HttpOptions& options)
    : access_(options.tokens, options.private_reads),
      admission_(store, executor, {options.max_queued_per_user, options.max_memory_bytes, options.max_sphere_steps, options.max_user_bytes},
                 options.machine_speed),
      worker_secrets_(store),
      context_{store, executor, access_, admission_, worker_secrets_, std::size_t(options.max_jobs_per_sweep),
               std::size_t(options.max_sweep_bytes)} {
  router_.set_gate([this](const http::Request& req, http::Response& res) { return access_.gate(req, res); });
  transport_ = std::make_unique<http::Transport>(router_, connection_options(options, worker_secrets_));
}

HttpServer::~HttpServer() = default;

int HttpServer::bind(const std::string& host, int port) { return transport_->bind(host, port); }
void HttpServer::serve() { transport_->serve(); }
void HttpServer::stop() { transport_->stop(); }

}  // namespace granulab::server
