// The daemon's connections, so that no client can hold a thread it is not using. One poll thread owns
// every connection that is idle, still sending its request, or slow to read its answer: it reads what
// arrives and feeds a RequestReader, writes answers as the socket takes them, and drops connections whose
// request is not complete within `request_timeout_ms` (slow senders: 408), that stay idle past
// `keep_alive_timeout_ms`, or whose answer makes no progress for `write_timeout_ms` (slow readers). Only
// complete requests reach the handler threads, which turn them into answers in memory and hand both back.
// Idle, slow and non-reading clients therefore cost a file descriptor and some bytes, never a handler
// thread: /v1/health answers while dozens of them are open.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <sys/types.h>

#include "server/request_reader.h"

struct ssl_st;
struct ssl_ctx_st;

namespace granulab::server {

struct ConnectionOptions {
  RequestLimits limits;
  int handler_threads = 8;
  int max_connections = 512;          ///< more open connections are answered 503 and closed
  /// One address (an IP) may hold at most this many of them (503 past it): a client re-opening every socket
  /// it loses cannot take the slots of others. 0: a quarter of max_connections (a lab behind one NAT address
  /// keeps room), all of them when there are at most 16.
  int max_connections_per_peer = 0;
  int request_timeout_ms = 10000;     ///< from a request's first byte to its last
  int keep_alive_timeout_ms = 5000;   ///< idle time allowed between requests on one connection
  int keep_alive_max_requests = 100;  ///< requests per connection before it is closed
  int write_timeout_ms = 10000;       ///< an answer that makes no progress for this long is abandoned
  /// A trusted request (RequestLimits::trusted: a job's worker sending a checkpoint) has this long instead
  /// of request_timeout_ms, from the moment its head is read.
  int trusted_request_timeout_ms = 600000;
  /// PEM files: with both, every connection speaks TLS (1.2 or later) and nothing else.
  std::string tls_cert_file, tls_key_file;
};

/// Sends all of `data` on `fd` (blocking or not), waiting at most `timeout_ms` each time the socket is
/// full. False when the peer is gone or stalled.
bool send_all(int fd, const char* data, std::size_t size, int timeout_ms);

class ConnectionLoop {
 public:
  /// Answers one complete request read from `fd`: appends the whole answer to `response` and returns
  /// whether the connection may serve another. `last` says this is the connection's last request.
  using Handler = std::function<bool(int fd, const std::string& request, bool last, std::string& response)>;

  ConnectionLoop(const ConnectionOptions& options, Handler handler);
  ~ConnectionLoop();
  ConnectionLoop(const ConnectionLoop&) = delete;
  ConnectionLoop& operator=(const ConnectionLoop&) = delete;

  /// Takes ownership of an accepted socket (closes it in the end, whatever happens).
  void adopt(int fd);
  /// Closes every connection and joins the threads; requests being answered finish first.
  void stop();
  int open_connections() const { return open_; }

 private:
  struct Connection {
    RequestReader reader;
    std::int64_t deadline_ms = 0;
    int served = 0;                 ///< requests answered on this connection
    bool draining = false;          ///< rejected or done: reading and discarding until the peer closes or the deadline
    std::string out;                ///< the answer being written
    std::size_t out_at = 0;         ///< bytes of it already sent
    bool close_after = false;       ///< close once `out` is sent
    bool trusted_deadline = false;  ///< the deadline is already the trusted request's
    short tls_want = 0;             ///< TLS asked to wait for this poll event before the last call is retried
    bool writing() const { return out_at < out.size(); }
  };
  struct Handed {  ///< a connection entering the poll thread: new, or back from a handler with its answer
    int fd;
    int served;
    std::string leftover, response;
    bool keep = true;
  };
  struct Work {
    int fd;
    int served;
    std::string request, leftover;
  };

  void poll_loop();
  void handler_loop();
  void admit(Handed h, std::int64_t now);
  void on_readable(int fd, std::int64_t now);
  void on_writable(int fd, std::int64_t now);
  void after_feed(int fd, Connection& c, std::int64_t now);
  void reject(int fd, Connection& c, int status, const std::string& code, const std::string& message, std::int64_t now);
  void drain(int fd, Connection& c, std::int64_t now);
  void close_connection(int fd);
  void wake();
  /// Counts `fd` against its peer's share; false (and nothing counted) when that peer holds its limit.
  bool take_peer_slot(int fd, std::string& peer);
  /// TLS: the connection's session (nullptr without TLS); reads and writes through it, or the socket.
  ssl_st* tls_of(int fd);
  ssize_t read_some(int fd, Connection& c, char* buffer, std::size_t size);
  ssize_t write_some(int fd, Connection& c, const char* data, std::size_t size);
  /// An answer sent at once (an error, 100 Continue), through TLS when on; false when the peer is gone.
  bool send_now(int fd, const std::string& text, int timeout_ms);
  int peer_limit() const;
  void release_peer_slot(int fd);

  ConnectionOptions options_;
  Handler handler_;
  std::atomic<int> open_{0};
  std::atomic<bool> stopping_{false};
  int wake_fd_ = -1;

  std::map<int, Connection> connections_;  ///< owned by the poll thread only

  ssl_ctx_st* tls_ = nullptr;            ///< the server's TLS context; nullptr: plain HTTP
  std::mutex tls_mutex_;
  std::map<int, ssl_st*> sessions_;      ///< each TLS connection's session, by socket

  std::mutex peers_mutex_;
  std::map<std::string, int> per_peer_;  ///< open connections by peer address
  std::map<int, std::string> peer_of_;   ///< each counted socket's peer

  std::mutex mutex_;
  std::vector<Handed> incoming_;
  std::deque<Work> work_;
  std::condition_variable work_ready_;

  std::thread poller_;
  std::vector<std::thread> handlers_;
};

}  // namespace granulab::server
