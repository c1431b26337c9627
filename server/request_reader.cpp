#include "server/request_reader.h"

#include <algorithm>
#include <cctype>

namespace granulab::server {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// The end of the first line in `s` from `from`: the index of its '\n' and the line without "\r\n".
bool next_line(const std::string& s, std::size_t from, std::size_t& newline, std::string& line) {
  newline = s.find('\n', from);
  if (newline == std::string::npos) return false;
  line = s.substr(from, newline - from);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

}  // namespace

RequestReader::RequestReader(const RequestLimits& limits, std::string already_received)
    : limits_(limits), buffer_(std::move(already_received)) {
  received_ = !buffer_.empty();
  advance();
}

RequestReader::State RequestReader::feed(const char* data, std::size_t size) {
  if (state_ != State::need_more) return state_;
  buffer_.append(data, size);
  received_ = received_ || size > 0;
  return advance();
}

bool RequestReader::take_continue() {
  const bool send = continue_pending_;
  continue_pending_ = false;
  return send;
}

std::string RequestReader::take_request() { return std::move(request_); }
std::string RequestReader::take_leftover() { return std::move(leftover_); }

RequestReader::State RequestReader::reject(int status, const std::string& code, const std::string& message) {
  reject_status_ = status;
  reject_code_ = code;
  reject_message_ = message;
  continue_pending_ = false;
  return state_ = State::rejected;
}

RequestReader::State RequestReader::finish(std::size_t consumed) {
  const std::string body = chunked_ ? std::move(body_) : buffer_.substr(0, consumed);
  request_ = head_ + "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  leftover_ = buffer_.substr(consumed);
  buffer_.clear();
  return state_ = State::complete;
}

RequestReader::State RequestReader::advance() {
  if (state_ != State::need_more) return state_;
  if (!head_done_) {
    // Blank lines before a request line are allowed (RFC 9112 2.2), e.g. after a previous body's CRLF.
    const auto first = buffer_.find_first_not_of("\r\n");
    buffer_.erase(0, first == std::string::npos ? buffer_.size() : first);
    const auto crlf = buffer_.find("\r\n\r\n"), lf = buffer_.find("\n\n");
    const std::size_t end = std::min(crlf, lf);
    if (end == std::string::npos || end > limits_.max_head_bytes) {
      if (buffer_.size() > limits_.max_head_bytes)
        return reject(
            431, "head_too_large",
            "request line and headers larger than the limit of " + std::to_string(limits_.max_head_bytes) + " bytes");
      return state_;
    }
    if (parse_head(end, end == crlf ? 4 : 2) != State::need_more) return state_;
  }
  if (chunked_) return read_chunks();
  if (buffer_.size() >= content_length_) return finish(content_length_);
  return state_;
}

RequestReader::State RequestReader::parse_head(std::size_t head_end, std::size_t terminator) {
  const std::string head = buffer_.substr(0, head_end) + "\n";
  buffer_.erase(0, head_end + terminator);
  head_done_ = true;
  std::size_t pos = 0, newline = 0;
  std::string line, target, worker_token;
  bool has_length = false, expect_continue = false;
  for (bool request_line = true; next_line(head, pos, newline, line); pos = newline + 1, request_line = false) {
    if (request_line) {
      head_ = line + "\r\n";
      const auto first = line.find(' '), second = line.find(' ', first == std::string::npos ? first : first + 1);
      if (first != std::string::npos && second != std::string::npos)
        target = line.substr(first + 1, second - first - 1);
      continue;
    }
    // Strict names: no folded lines (a leading space or tab), no space in or after a name. Lenient parsing
    // here, and a proxy in front parsing strictly, is how requests get smuggled past it.
    const auto colon = line.find(':');
    if (colon == std::string::npos || colon == 0 || line.find_first_of(" \t") < colon)
      return reject(400, "bad_request",
                    "malformed header line (expected 'Name: value', no folding, no space in the name)");
    const std::string name = lower(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    if (line.size() > kMaxHeaderLineBytes)
      return reject(431, "header_too_large",
                    "the header '" + line.substr(0, std::min<std::size_t>(colon, 64)) + "' is " +
                        std::to_string(line.size()) + " bytes, over the limit of " +
                        std::to_string(kMaxHeaderLineBytes) + " bytes per header line");
    if (name == "content-length") {
      const bool digits =
          !value.empty() && std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
      if (!digits)
        return reject(400, "bad_request",
                      "Content-Length must be a number of bytes, got '" + value.substr(0, 32) + "'");
      if (value.size() > 18)  // more than any body could be: no need to parse it
        return reject(413, "too_large",
                      "request body larger than the limit of " + std::to_string(limits_.max_body_bytes) + " bytes");
      const std::size_t length = std::stoull(value);  // cannot throw: 1 to 18 digits
      if (has_length && length != content_length_)
        return reject(400, "bad_request", "two different Content-Length headers");
      has_length = true;
      content_length_ = length;
    } else if (name == "transfer-encoding") {
      if (lower(value) != "chunked")
        // 400, not 501: a request the server cannot read is the client's to fix, and no 5xx is the rule.
        return reject(400, "bad_request", "only 'Transfer-Encoding: chunked' is supported, got '" + value + "'");
      chunked_ = true;
    } else if (name == "content-encoding") {
      // cpp-httplib would inflate a gzip body after the size check: 1 MiB of gzip is a gigabyte of JSON.
      if (lower(value) != "identity")
        return reject(415, "unsupported_encoding",
                      "request bodies must not be compressed, got 'Content-Encoding: " + value + "'");
    } else if (name == "expect") {
      if (lower(value) != "100-continue")
        return reject(417, "expectation_failed", "only 'Expect: 100-continue' is supported, got '" + value + "'");
      expect_continue = true;
    } else if (name == "content-type" && lower(value).rfind("application/x-www-form-urlencoded", 0) == 0) {
      // `curl -d @spec.json` sends JSON labelled as a form. Every route reads its body as the bytes it is;
      // cpp-httplib would also split a form body into parameters, and refuse one over 8 KiB (413).
      head_ += "Content-Type: application/octet-stream\r\n";
    } else {
      if (name == "x-worker-token") worker_token = value;
      head_ += line + "\r\n";
    }
  }
  body_limit_ = limits_.max_body_bytes;
  if (limits_.trusted && !worker_token.empty() && limits_.max_trusted_body_bytes > body_limit_ &&
      limits_.trusted(target, worker_token))
    body_limit_ = limits_.max_trusted_body_bytes;
  if (chunked_ && has_length)
    return reject(400, "bad_request", "a request may not have both Content-Length and Transfer-Encoding");
  if (content_length_ > body_limit_)
    return reject(413, "too_large",
                  "request body of " + std::to_string(content_length_) + " bytes is larger than the limit of " +
                      std::to_string(body_limit_) + " bytes");
  // A POST with neither header has an empty body (content_length_ stays 0).
  continue_pending_ = expect_continue && (chunked_ || content_length_ > 0) && buffer_.empty();
  return state_;
}

RequestReader::State RequestReader::read_chunks() {
  // Parsed from an offset and erased once at the end: erasing per chunk made many small chunks cost
  // the square of the buffer (a gigabyte of copying per 64 KiB of 1-byte chunks).
  std::size_t at = 0, newline = 0;
  std::string line;
  const auto wait = [&] {
    buffer_.erase(0, at);
    return state_;
  };
  while (true) {
    switch (chunk_) {
      case Chunk::size_line: {
        if (!next_line(buffer_, at, newline, line)) {
          if (buffer_.size() - at > 1024) return reject(400, "bad_request", "chunk size line longer than 1024 bytes");
          return wait();
        }
        const std::string hex = trim(line.substr(0, line.find(';')));
        const bool valid = !hex.empty() && hex.size() <= 15 && std::all_of(hex.begin(), hex.end(), [](char c) {
          return std::isxdigit(static_cast<unsigned char>(c));
        });
        if (!valid) return reject(400, "bad_request", "malformed chunk size '" + hex.substr(0, 32) + "'");
        chunk_remaining_ = std::stoull(hex, nullptr, 16);  // cannot throw: 1 to 15 hex digits
        at = newline + 1;
        if (chunk_remaining_ == 0) {
          chunk_ = Chunk::trailer;
        } else if (body_.size() + chunk_remaining_ > body_limit_) {
          return reject(413, "too_large",
                        "chunked request body larger than the limit of " + std::to_string(body_limit_) + " bytes");
        } else {
          chunk_ = Chunk::data;
        }
        break;
      }
      case Chunk::data: {
        const std::size_t take = std::min(chunk_remaining_, buffer_.size() - at);
        body_.append(buffer_, at, take);
        at += take;
        chunk_remaining_ -= take;
        if (chunk_remaining_ > 0) return wait();
        chunk_ = Chunk::data_end;
        break;
      }
      case Chunk::data_end:
        if (!next_line(buffer_, at, newline, line)) {
          if (buffer_.size() - at > 2) return reject(400, "bad_request", "chunk data longer than its size");
          return wait();
        }
        if (!line.empty()) return reject(400, "bad_request", "chunk data longer than its size");
        at = newline + 1;
        chunk_ = Chunk::size_line;
        break;
      case Chunk::trailer:
        if (!next_line(buffer_, at, newline, line)) {
          if (buffer_.size() - at > limits_.max_head_bytes)
            return reject(400, "bad_request", "chunked trailer too long");
          return wait();
        }
        at = newline + 1;
        trailer_bytes_ += line.size() + 2;
        if (trailer_bytes_ > limits_.max_head_bytes)
          return reject(400, "bad_request",
                        "chunked trailer longer than " + std::to_string(limits_.max_head_bytes) + " bytes");
        if (line.empty()) {  // trailer fields are dropped
          buffer_.erase(0, at);
          return finish(0);
        }
        break;
    }
  }
}

}  // namespace granulab::server
