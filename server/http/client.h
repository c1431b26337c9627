// A small blocking HTTP/1.1 client for the daemon's own outgoing calls (the Slurm REST API): one
// connection, kept alive, with timeouts. Implemented in httplib_adapter.cpp.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace granulab::server::http {

class Client {
 public:
  struct Answer {
    int status = 0;
    std::string body;
  };
  /// `base_url`: scheme, host and port, e.g. http://127.0.0.1:6820. Timeouts in seconds.
  Client(const std::string& base_url, int connect_timeout_s, int read_timeout_s, int write_timeout_s);
  ~Client();
  /// False when `base_url` cannot be used (an unknown scheme, no host).
  bool valid() const;
  /// One request (GET, POST or DELETE); nullopt when there was no answer, with `problem` saying why.
  std::optional<Answer> send(const std::string& method, const std::string& path,
                             const std::vector<std::pair<std::string, std::string>>& headers, const std::string& body,
                             const std::string& content_type, std::string& problem);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granulab::server::http
