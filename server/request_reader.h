// Reads one HTTP/1.1 request from bytes as they arrive, before cpp-httplib sees it, so that the limits
// hold whatever the client does: the head and the body are bounded (chunked bodies too, decoded here),
// `Expect: 100-continue` is answered, and a POST without a body or Content-Length is an empty body.
// The complete request is handed on rewritten with an exact Content-Length and no Transfer-Encoding or
// Expect header, so cpp-httplib only ever reads a known number of bytes that are already in memory.
// No sockets here: the connection loop feeds it, which keeps it testable byte by byte.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace granulab::server {

/// B; cpp-httplib (a compiled Debian library, its limits fixed) answers 400 to a header line of 8,192 bytes
/// or more with its CRLF: the reader refuses a line over this first, with a 431 that names the limit.
constexpr std::size_t kMaxHeaderLineBytes = 8000;

struct RequestLimits {
  std::size_t max_head_bytes = 16 * 1024;  ///< request line + headers
  std::size_t max_body_bytes = 1 << 20;    ///< the body after chunked decoding
  /// A larger limit for a request whose `X-Worker-Token` header `trusted` accepts for its target (a job's
  /// worker on a cluster sending a checkpoint): decided from the head, before any of the body is read.
  std::size_t max_trusted_body_bytes = 0;
  std::function<bool(const std::string& target, const std::string& worker_token)> trusted;
};

class RequestReader {
 public:
  enum class State { need_more, complete, rejected };

  explicit RequestReader(const RequestLimits& limits, std::string already_received = "");

  /// Appends received bytes and advances; returns the state reached.
  State feed(const char* data, std::size_t size);
  State state() const { return state_; }
  /// True once any byte of this request has arrived, blank lines included (the request deadline runs
  /// from then: a client cannot keep a connection by sending CRLFs).
  bool started() const { return received_; }
  /// True exactly once, when the head asked for `100-continue` and the announced body is acceptable:
  /// the caller sends "HTTP/1.1 100 Continue" then.
  bool take_continue();
  /// True once the head was read and the request was trusted with the larger body limit.
  bool trusted() const { return body_limit_ > limits_.max_body_bytes; }

  /// When complete: the request as cpp-httplib should read it, and the bytes after it (a pipelined
  /// next request), which start the next reader.
  std::string take_request();
  std::string take_leftover();

  /// When rejected: the HTTP status, error code and a message naming the limit.
  int reject_status() const { return reject_status_; }
  const std::string& reject_code() const { return reject_code_; }
  const std::string& reject_message() const { return reject_message_; }

 private:
  State advance();
  State parse_head(std::size_t head_end, std::size_t terminator);
  State read_chunks();
  State reject(int status, const std::string& code, const std::string& message);
  State finish(std::size_t consumed);

  RequestLimits limits_;
  State state_ = State::need_more;
  std::string buffer_;  ///< bytes not yet consumed
  bool head_done_ = false;
  std::string head_;  ///< request line + headers kept, without the final blank line
  bool chunked_ = false;
  enum class Chunk { size_line, data, data_end, trailer } chunk_ = Chunk::size_line;
  std::size_t chunk_remaining_ = 0;
  std::size_t trailer_bytes_ = 0;
  bool received_ = false;
  std::size_t content_length_ = 0;
  std::size_t body_limit_ = 0;  ///< max_body_bytes, or max_trusted_body_bytes for a trusted request
  std::string body_;            ///< decoded chunked body so far
  bool continue_pending_ = false;
  std::string request_, leftover_;
  int reject_status_ = 0;
  std::string reject_code_, reject_message_;
};

}  // namespace granulab::server
