#include "server/connection_loop.h"

#include <algorithm>
#include <cerrno>
#include <chrono>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <openssl/err.h>
#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

namespace granulab::server {

namespace {

std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

const char* reason(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 408: return "Request Timeout";
    case 413: return "Payload Too Large";
    case 415: return "Unsupported Media Type";
    case 417: return "Expectation Failed";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    default: return "Error";
  }
}

// A complete error response, closing the connection, in the JSON shape of every other error.
std::string error_response(int status, const std::string& code, const std::string& message) {
  const nlohmann::json body = {{"error", {{"code", code}, {"message", message}, {"field", ""}}}};
  const std::string text = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  return "HTTP/1.1 " + std::to_string(status) + " " + reason(status) +
         "\r\nContent-Type: application/json\r\nConnection: close\r\nContent-Length: " + std::to_string(text.size()) +
         "\r\n\r\n" + text;
}

}  // namespace

bool send_all(int fd, const char* data, std::size_t size, int timeout_ms) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n > 0) {
      data += n;
      size -= std::size_t(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{fd, POLLOUT, 0};
      if (::poll(&p, 1, timeout_ms) <= 0 || (p.revents & (POLLERR | POLLHUP))) return false;
      continue;
    }
    return false;
  }
  return true;
}

namespace {

std::string openssl_error() {
  const unsigned long code = ERR_get_error();
  char text[256] = "unknown error";
  if (code) ERR_error_string_n(code, text, sizeof text);
  ERR_clear_error();
  return text;
}

// The server's TLS context: the certificate chain and key of --tls-cert / --tls-key, TLS 1.2 or later.
SSL_CTX* make_tls_context(const std::string& cert, const std::string& key) {
  SSL_CTX* ctx = SSL_CTX_new(TLS_server_method());
  if (!ctx) throw std::runtime_error("TLS: cannot make a context: " + openssl_error());
  const auto fail = [&](const std::string& what) {
    const std::string why = openssl_error();
    SSL_CTX_free(ctx);
    throw std::runtime_error("TLS: " + what + ": " + why);
  };
  SSL_CTX_set_min_proto_version(ctx, TLS1_2_VERSION);
  if (SSL_CTX_use_certificate_chain_file(ctx, cert.c_str()) != 1) fail("cannot read the certificate '" + cert + "'");
  if (SSL_CTX_use_PrivateKey_file(ctx, key.c_str(), SSL_FILETYPE_PEM) != 1) fail("cannot read the key '" + key + "'");
  if (SSL_CTX_check_private_key(ctx) != 1) fail("the key '" + key + "' is not the certificate's");
  // Writes may be partial (the loop keeps what is left) and retried from a string that may have moved.
  SSL_CTX_set_mode(ctx, SSL_MODE_ENABLE_PARTIAL_WRITE | SSL_MODE_ACCEPT_MOVING_WRITE_BUFFER | SSL_MODE_RELEASE_BUFFERS);
  SSL_CTX_set_options(ctx, SSL_OP_NO_RENEGOTIATION);
  SSL_CTX_set_num_tickets(ctx, 0);  // no session tickets to write after the handshake
  return ctx;
}

}  // namespace

ConnectionLoop::ConnectionLoop(const ConnectionOptions& options, Handler handler)
    : options_(options), handler_(std::move(handler)) {
  if (!options_.tls_cert_file.empty() || !options_.tls_key_file.empty()) {
    if (options_.tls_cert_file.empty() || options_.tls_key_file.empty())
      throw std::invalid_argument("TLS needs both a certificate and its key (--tls-cert and --tls-key)");
    tls_ = make_tls_context(options_.tls_cert_file, options_.tls_key_file);
  }
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error("eventfd failed");
  poller_ = std::thread([this] { poll_loop(); });
  for (int i = 0; i < std::max(1, options_.handler_threads); ++i) handlers_.emplace_back([this] { handler_loop(); });
}

ConnectionLoop::~ConnectionLoop() {
  stop();
  if (tls_) SSL_CTX_free(tls_);
  ::close(wake_fd_);
}

void ConnectionLoop::wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_fd_, &one, sizeof one);
}

SSL* ConnectionLoop::tls_of(int fd) {
  if (!tls_) return nullptr;
  std::lock_guard<std::mutex> lock(tls_mutex_);
  const auto it = sessions_.find(fd);
  return it == sessions_.end() ? nullptr : it->second;
}

// Through TLS, a call that cannot go on says which way the socket must become ready (WANT_READ or
// WANT_WRITE, either way for a read or a write during a handshake): kept in c.tls_want for the poll, and
// the same call is made again then. -1 with EAGAIN for that; 0 for a closed or failed connection.
namespace {

// What an SSL_read or SSL_write that returned `n` means for the loop (see read_some).
ssize_t tls_outcome(SSL* ssl, int n, short& want) {
  if (n > 0) return n;
  const int error = SSL_get_error(ssl, n);
  if (error == SSL_ERROR_WANT_READ || error == SSL_ERROR_WANT_WRITE) {
    want = error == SSL_ERROR_WANT_READ ? POLLIN : POLLOUT;
    errno = EAGAIN;
    return -1;
  }
  ERR_clear_error();  // a client speaking plain HTTP to the TLS port, a reset: the connection ends
  return 0;
}

}  // namespace

ssize_t ConnectionLoop::read_some(int fd, Connection& c, char* buffer, std::size_t size) {
  SSL* ssl = c.draining ? nullptr : tls_of(fd);  // a draining connection's bytes are discarded unread
  if (!ssl) return ::recv(fd, buffer, size, 0);
  c.tls_want = 0;
  ERR_clear_error();
  return tls_outcome(ssl, SSL_read(ssl, buffer, int(std::min<std::size_t>(size, 1 << 30))), c.tls_want);
}

ssize_t ConnectionLoop::write_some(int fd, Connection& c, const char* data, std::size_t size) {
  SSL* ssl = tls_of(fd);
  if (!ssl) return ::send(fd, data, size, MSG_NOSIGNAL);
  c.tls_want = 0;
  ERR_clear_error();
  return tls_outcome(ssl, SSL_write(ssl, data, int(std::min<std::size_t>(size, 1 << 30))), c.tls_want);
}

bool ConnectionLoop::send_now(int fd, const std::string& text, int timeout_ms) {
  SSL* ssl = tls_of(fd);
  if (!ssl) return send_all(fd, text.data(), text.size(), timeout_ms);
  if (!SSL_is_init_finished(ssl)) return false;  // no session to speak in yet
  std::size_t at = 0;
  while (at < text.size()) {
    ERR_clear_error();
    const int n = SSL_write(ssl, text.data() + at, int(text.size() - at));
    if (n > 0) {
      at += std::size_t(n);
      continue;
    }
    const int error = SSL_get_error(ssl, n);
    if (error != SSL_ERROR_WANT_READ && error != SSL_ERROR_WANT_WRITE) {
      ERR_clear_error();
      return false;
    }
    pollfd p{fd, short(error == SSL_ERROR_WANT_READ ? POLLIN : POLLOUT), 0};
    if (::poll(&p, 1, timeout_ms) <= 0 || (p.revents & (POLLERR | POLLHUP))) return false;
  }
  return true;
}

int ConnectionLoop::peer_limit() const {
  if (options_.max_connections_per_peer > 0) return options_.max_connections_per_peer;
  return std::max(std::min(options_.max_connections, 16), options_.max_connections / 4);
}

bool ConnectionLoop::take_peer_slot(int fd, std::string& peer) {
  sockaddr_storage a{};
  socklen_t length = sizeof a;
  char text[INET6_ADDRSTRLEN] = "?";
  if (::getpeername(fd, reinterpret_cast<sockaddr*>(&a), &length) == 0) {
    if (a.ss_family == AF_INET)
      ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(&a)->sin_addr, text, sizeof text);
    else if (a.ss_family == AF_INET6)
      ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(&a)->sin6_addr, text, sizeof text);
  }
  peer = text;
  const int limit = peer_limit();
  std::lock_guard<std::mutex> lock(peers_mutex_);
  int& held = per_peer_[peer];
  if (held >= limit) {
    if (held == 0) per_peer_.erase(peer);
    return false;
  }
  ++held;
  peer_of_[fd] = peer;
  return true;
}

void ConnectionLoop::release_peer_slot(int fd) {
  std::lock_guard<std::mutex> lock(peers_mutex_);
  const auto it = peer_of_.find(fd);
  if (it == peer_of_.end()) return;
  if (--per_peer_[it->second] <= 0) per_peer_.erase(it->second);
  peer_of_.erase(it);
}

void ConnectionLoop::adopt(int fd) {
  // Over a limit, plain HTTP gets a 503 that names it; TLS is closed before any handshake (a handshake
  // to say no would spend what the limit protects).
  std::string peer;
  if (!take_peer_slot(fd, peer)) {
    const int limit = peer_limit();
    const std::string text = error_response(
        503, "too_many_connections",
        "the address " + peer + " has " + std::to_string(limit) +
            " open connections, the most one address may hold (max_connections_per_peer); close some or retry");
    if (!tls_) send_all(fd, text.data(), text.size(), 0);
    ::close(fd);
    return;
  }
  if (++open_ > options_.max_connections) {
    const std::string text = error_response(
        503, "too_many_connections",
        "the server has " + std::to_string(options_.max_connections) + " open connections (max_connections); retry");
    if (!tls_) send_all(fd, text.data(), text.size(), 0);
    release_peer_slot(fd);
    ::close(fd);
    --open_;
    return;
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
  // Answers go out at once: with Nagle's algorithm a kept-alive connection waited for the client's
  // delayed ACK on every request (38 requests/s instead of thousands).
  int yes = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  if (tls_) {
    SSL* ssl = SSL_new(tls_);
    if (!ssl || SSL_set_fd(ssl, fd) != 1) {
      if (ssl) SSL_free(ssl);
      ERR_clear_error();
      return close_connection(fd);
    }
    SSL_set_accept_state(ssl);  // the handshake runs inside the first reads
    std::lock_guard<std::mutex> lock(tls_mutex_);
    sessions_[fd] = ssl;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);  // with stop(): a socket is either taken in or closed, never lost
    if (stopping_) {
      close_connection(fd);
      return;
    }
    incoming_.push_back({fd, 0, "", "", true});
  }
  wake();
}

void ConnectionLoop::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_.exchange(true)) return;
  }
  wake();
  work_ready_.notify_all();
  if (poller_.joinable()) poller_.join();
  for (auto& t : handlers_)
    if (t.joinable()) t.join();
  // Answers made after the poll thread stopped: sent if the socket takes them at once, then closed.
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Work& w : work_) close_connection(w.fd);
  for (const Handed& h : incoming_) {
    send_now(h.fd, h.response, 100);
    close_connection(h.fd);
  }
  work_.clear();
  incoming_.clear();
}

void ConnectionLoop::close_connection(int fd) {
  if (tls_) {
    std::lock_guard<std::mutex> lock(tls_mutex_);
    const auto it = sessions_.find(fd);
    if (it != sessions_.end()) {
      SSL_free(it->second);  // the socket BIO leaves the socket to us
      sessions_.erase(it);
    }
  }
  release_peer_slot(fd);  // before the close: once closed, the number may be another socket's
  ::close(fd);
  --open_;
}

void ConnectionLoop::admit(Handed h, std::int64_t now) {
  Connection& c =
      connections_.emplace(h.fd, Connection{RequestReader(options_.limits, std::move(h.leftover))}).first->second;
  c.served = h.served;
  if (!h.response.empty()) {  // the answer first; the next request (maybe already here) after it
    c.out = std::move(h.response);
    c.close_after = !h.keep;
    c.deadline_ms = now + options_.write_timeout_ms;
    return;
  }
  c.deadline_ms = now + (c.reader.started() ? options_.request_timeout_ms : options_.keep_alive_timeout_ms);
  after_feed(h.fd, c, now);
}

// Stop writing, then read and discard for a moment before closing: closing with unread bytes would reset
// the connection and could destroy the answer before the client reads it.
void ConnectionLoop::drain(int fd, Connection& c, std::int64_t now) {
  if (SSL* ssl = tls_of(fd); ssl && SSL_is_init_finished(ssl)) {
    SSL_shutdown(ssl);  // best effort: its close_notify, if the socket takes it now
    ERR_clear_error();
  }
  ::shutdown(fd, SHUT_WR);
  c.draining = true;
  c.out.clear();
  c.out_at = 0;
  c.deadline_ms = now + 2000;
}

void ConnectionLoop::reject(int fd, Connection& c, int status, const std::string& code, const std::string& message,
                            std::int64_t now) {
  const std::string text = error_response(status, code, message);
  if (tls_of(fd)) {
    // Through the session like any answer: the loop writes it, then drains.
    c.out = text;
    c.out_at = 0;
    c.close_after = true;
    c.deadline_ms = now + options_.write_timeout_ms;
    return;
  }
  send_all(fd, text.data(), text.size(), 0);
  drain(fd, c, now);
}

void ConnectionLoop::after_feed(int fd, Connection& c, std::int64_t now) {
  if (c.reader.take_continue()) {
    send_now(fd, "HTTP/1.1 100 Continue\r\n\r\n", 100);
  }
  switch (c.reader.state()) {
    case RequestReader::State::need_more:
      if (c.reader.trusted() && !c.trusted_deadline) {
        c.deadline_ms = now + options_.trusted_request_timeout_ms;
        c.trusted_deadline = true;
      }
      return;
    case RequestReader::State::rejected:
      return reject(fd, c, c.reader.reject_status(), c.reader.reject_code(), c.reader.reject_message(), now);
    case RequestReader::State::complete: {
      Work w{fd, c.served, c.reader.take_request(), c.reader.take_leftover()};
      connections_.erase(fd);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        work_.push_back(std::move(w));
      }
      work_ready_.notify_one();
      return;
    }
  }
}

void ConnectionLoop::on_readable(int fd, std::int64_t now) {
  Connection& c = connections_.at(fd);
  char buffer[64 * 1024];
  const ssize_t n = read_some(fd, c, buffer, sizeof buffer);
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
  if (n <= 0) {
    connections_.erase(fd);
    return close_connection(fd);
  }
  if (c.draining) return;  // discarded
  if (!c.reader.started()) c.deadline_ms = now + options_.request_timeout_ms;
  c.reader.feed(buffer, std::size_t(n));
  after_feed(fd, c, now);
}

void ConnectionLoop::on_writable(int fd, std::int64_t now) {
  Connection& c = connections_.at(fd);
  const ssize_t n = write_some(fd, c, c.out.data() + c.out_at, c.out.size() - c.out_at);
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
  if (n <= 0) {
    connections_.erase(fd);
    return close_connection(fd);
  }
  c.out_at += std::size_t(n);
  c.deadline_ms = now + options_.write_timeout_ms;  // progress: a slow reader, not a stalled one
  if (c.writing()) return;
  c.out.clear();
  c.out_at = 0;
  if (c.close_after) return drain(fd, c, now);
  // The next request: it may already be here (pipelined), or not yet begun.
  c.deadline_ms = now + (c.reader.started() ? options_.request_timeout_ms : options_.keep_alive_timeout_ms);
  after_feed(fd, c, now);
}

void ConnectionLoop::poll_loop() {
  std::vector<pollfd> polled;
  while (!stopping_) {
    std::int64_t now = now_ms();
    std::vector<Handed> arrived;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      arrived.swap(incoming_);
    }
    for (Handed& h : arrived) admit(std::move(h), now);

    polled.assign(1, pollfd{wake_fd_, POLLIN, 0});
    std::int64_t next_deadline = now + 1000;
    for (const auto& [fd, c] : connections_) {
      // While an answer goes out, nothing more is read: a client must take its answers to send more.
      // Through TLS, the way the last call asked to wait (a read may need to write during a handshake).
      polled.push_back({fd, short(c.tls_want ? c.tls_want : c.writing() ? POLLOUT : POLLIN), 0});
      next_deadline = std::min(next_deadline, c.deadline_ms);
    }
    const int ready = ::poll(polled.data(), polled.size(), int(std::max<std::int64_t>(0, next_deadline - now)));
    if (ready < 0 && errno != EINTR) {
      spdlog::error("poll failed: errno {}", errno);
      break;
    }
    now = now_ms();
    if (polled[0].revents & POLLIN) {
      std::uint64_t count = 0;
      [[maybe_unused]] const ssize_t n = ::read(wake_fd_, &count, sizeof count);
    }
    for (std::size_t i = 1; i < polled.size(); ++i) {
      const auto it = connections_.find(polled[i].fd);
      if (!polled[i].revents || it == connections_.end()) continue;
      if (it->second.writing()) on_writable(polled[i].fd, now);
      else on_readable(polled[i].fd, now);
    }

    // Deadlines: a request still arriving is a slow sender (408, then a moment to read it); an idle,
    // stalled-reading or draining connection just closes.
    for (auto it = connections_.begin(); it != connections_.end();) {
      const int fd = it->first;
      Connection& c = it->second;
      ++it;
      if (c.deadline_ms > now) continue;
      if (!c.draining && !c.writing() && c.reader.started()) {
        reject(fd, c, 408, "request_timeout",
               "the request was not complete within " + std::to_string(options_.request_timeout_ms) +
                   " ms (request_timeout)",
               now);
        continue;
      }
      connections_.erase(fd);
      close_connection(fd);
    }
  }
  for (const auto& [fd, c] : connections_) close_connection(fd);
  connections_.clear();
}

void ConnectionLoop::handler_loop() {
  while (true) {
    Work w;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_ready_.wait(lock, [this] { return stopping_ || !work_.empty(); });
      if (work_.empty()) return;  // stopping, nothing left to answer
      w = std::move(work_.front());
      work_.pop_front();
    }
    const bool last = w.served + 1 >= options_.keep_alive_max_requests || stopping_;
    Handed back{w.fd, w.served + 1, std::move(w.leftover), "", false};
    try {
      back.keep = handler_(w.fd, w.request, last, back.response) && !last;
    } catch (const std::exception& e) {
      spdlog::error("connection handler threw: {}", e.what());
    }
    if (back.response.empty() && !back.keep) {
      close_connection(w.fd);
      continue;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      incoming_.push_back(std::move(back));
    }
    wake();
  }
}

}  // namespace granulab::server
