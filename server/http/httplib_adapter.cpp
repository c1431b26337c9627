// The one file that includes cpp-httplib: the server side (Transport) parses the requests the
// ConnectionLoop has read whole and writes the answers it sends; the client side (Client) makes the
// daemon's outgoing calls. Everything above this file speaks http::Request and http::Response.
#include "server/http/client.h"
#include "server/http/transport.h"

#include <algorithm>
#include <atomic>
#include <cstdint>

#include <spdlog/spdlog.h>

#include "server/http/replies.h"
#include "server/store/sqlite.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

namespace granulab::server::http {

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

// The library's request as the routes see it, and their answer back.
void serve_with(const Router& router, const httplib::Request& in, httplib::Response& out) {
  Request req(in.body);
  req.method = in.method, req.path = in.path, req.target = in.target, req.remote_addr = in.remote_addr;
  // The URL's own query, not in.params: cpp-httplib also puts a form-encoded body's fields there.
  const auto mark = in.target.find('?');
  if (mark != std::string::npos) {
    httplib::Params query;
    httplib::detail::parse_query_text(in.target.substr(mark + 1), query);
    req.query.assign(query.begin(), query.end());
  }
  req.headers.assign(in.headers.begin(), in.headers.end());
  Response res;
  router.dispatch(req, res);
  out.status = res.status;
  for (auto& [name, value] : res.headers) out.set_header(name.c_str(), value);
  if (!res.content_type.empty()) out.set_header("Content-Type", res.content_type);
  out.body = std::move(res.body);
}

}  // namespace

struct Transport::Impl {
  LoopServer http;
  std::unique_ptr<ConnectionLoop> connections;
};

Transport::Transport(const Router& router, const ConnectionOptions& options) : impl_(std::make_unique<Impl>()) {
  LoopServer& http = impl_->http;
  impl_->connections = std::make_unique<ConnectionLoop>(
      options, [this](int fd, const std::string& request, bool last, std::string& response) {
        return impl_->http.answer(fd, request, last, response);
      });
  http.loop = impl_->connections.get();
  // The loop enforces both limits, before the library reads a byte.
  http.set_payload_max_length(std::max(options.limits.max_body_bytes, options.limits.max_trusted_body_bytes));
  // The Keep-Alive header cpp-httplib writes states the loop's policy.
  http.set_keep_alive_max_count(std::size_t(options.keep_alive_max_requests));
  http.set_keep_alive_timeout(std::max(1, options.keep_alive_timeout_ms / 1000));
  // Only SO_REUSEADDR: cpp-httplib's default adds SO_REUSEPORT, which let a second daemon bind the same
  // port and take half the requests.
  http.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // Answers go out at once: with Nagle's algorithm a kept-alive connection waited for the client's delayed
  // ACK on every request (26 ms each, 38 requests/s, against 4,000/s on fresh connections).
  http.set_tcp_nodelay(true);
  // The accept thread only hands sockets to the loop: one task thread is plenty.
  http.new_task_queue = [] { return new httplib::ThreadPool(1); };
  // Every request goes to the Router (which answers a path it does not know with a 404).
  const auto route = [&router](const httplib::Request& req, httplib::Response& res) { serve_with(router, req, res); };
  http.Get(".*", route).Post(".*", route).Delete(".*", route).Put(".*", route).Patch(".*", route);
  // Every response carries a request id; one access-log line per request.
  http.set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
    static std::atomic<std::uint64_t> next{1};
    // A 500 already has its own (the id the log names); headers are a multimap, so never add a second.
    if (!res.has_header("X-Request-Id")) res.set_header("X-Request-Id", std::to_string(next++));
  });
  // Nothing a handler throws reaches the framework or the client: a JSON 500 with the request id, and the
  // exception text only in the daemon's log.
  http.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown exception";
    bool full = false;
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const sqlite::StoreFull& e) {
      what = e.what(), full = true;
    } catch (const sqlite::Error& e) {
      what = std::string(e.what()) + " (in: " + e.sql + ")";  // the statement for the log only
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {}
    static std::atomic<std::uint64_t> next_error{1};
    const std::string id = "e" + std::to_string(next_error++);
    spdlog::error("{} {} -> {} ({}): {}", req.method, req.path, full ? 507 : 500, id, what);
    Response answer;
    if (full)
      error(answer, 507, "storage_full",
            "the server's storage is full (its disk, or --max-db-mb): nothing was stored; tell its administrator");
    else error(answer, 500, "internal", "internal error; the server's log has it under request id " + id);
    res.status = answer.status;
    res.set_header("X-Request-Id", id);
    res.set_content(answer.body, answer.content_type);
  });
  http.set_logger([](const httplib::Request& req, const httplib::Response& res) {
    spdlog::info("{} {} {} -> {} ({} bytes) id={}", req.remote_addr, req.method, req.path, res.status, res.body.size(),
                 res.get_header_value("X-Request-Id"));
  });
  // What the library answers itself (a request it cannot parse) is JSON like every other error.
  http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    Response answer;
    if (res.status == 413) error(answer, 413, "too_large", "request body too large");
    else if (res.status == 404) error(answer, 404, "not_found", "no such route");
    else if (res.status == 400) error(answer, 400, "bad_request", "malformed request");
    else if (res.status == 414)
      error(answer, 414, "uri_too_long", "the request's path and query are longer than 8 KiB");
    else error(answer, res.status, "http_error", "request failed with HTTP " + std::to_string(res.status));
    res.set_content(answer.body, answer.content_type);
  });
}

Transport::~Transport() {
  stop();
  impl_->connections->stop();
}

int Transport::bind(const std::string& host, int port) {
  LoopServer& http = impl_->http;
  const int bound = port == 0 ? http.bind_to_any_port(host) : (http.bind_to_port(host, port) ? port : -1);
  if (bound > 0) http.raise_backlog();
  return bound;
}

void Transport::serve() {
  impl_->http.listen_after_bind();
  impl_->connections->stop();  // answers what was already read, closes the rest
}

void Transport::stop() {
  if (impl_->http.is_running()) impl_->http.stop();
}

struct Client::Impl {
  explicit Impl(const std::string& url) : http(url) {}
  httplib::Client http;
};

Client::Client(const std::string& base_url, int connect_timeout_s, int read_timeout_s, int write_timeout_s)
    : impl_(std::make_unique<Impl>(base_url)) {
  impl_->http.set_connection_timeout(connect_timeout_s);
  impl_->http.set_read_timeout(read_timeout_s);
  impl_->http.set_write_timeout(write_timeout_s);
}

Client::~Client() = default;

bool Client::valid() const { return impl_->http.is_valid(); }

std::optional<Client::Answer> Client::send(const std::string& method, const std::string& path,
                                           const std::vector<std::pair<std::string, std::string>>& headers,
                                           const std::string& body, const std::string& content_type,
                                           std::string& problem) {
  const httplib::Headers h(headers.begin(), headers.end());
  const httplib::Result r = method == "POST"     ? impl_->http.Post(path, h, body, content_type.c_str())
                            : method == "DELETE" ? impl_->http.Delete(path, h)
                                                 : impl_->http.Get(path, h);
  if (!r) {
    problem = httplib::to_string(r.error());
    return std::nullopt;
  }
  return Answer{r->status, r->body};
}

}  // namespace granulab::server::http
