// One HTTP request and its answer as the route handlers see them: the transport (httplib_adapter.cpp)
// fills a Request from the wire and writes the Response back, so that no route, rule or test needs the
// HTTP library. Query parameters are the URL's own (a form-encoded body is never read as parameters).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace granulab::server::http {

struct Request {
  explicit Request(const std::string& body_bytes) : body(body_bytes) {}
  std::string method;                ///< GET, POST, DELETE (HEAD is answered as GET)
  std::string path;                  ///< without the query
  std::string target;                ///< path and query as sent
  std::string remote_addr;           ///< the peer's address, for the log
  const std::string& body;           ///< the whole body, already read and bounded by the connection loop
  std::vector<std::string> matches;  ///< [0] the path, then the route pattern's groups
  std::vector<std::pair<std::string, std::string>> query;    ///< decoded, in order
  std::vector<std::pair<std::string, std::string>> headers;  ///< as sent; looked up without regard to case

  bool has_param(std::string_view name) const;
  /// The first value of ?name= ("" when absent).
  std::string get_param_value(std::string_view name) const;
  bool has_header(std::string_view name) const;
  /// The first value of the header ("" when absent).
  std::string get_header_value(std::string_view name) const;
};

struct Response {
  int status = 200;
  std::string body;
  std::string content_type;
  std::vector<std::pair<std::string, std::string>> headers;

  void set_content(std::string text, std::string type) {
    body = std::move(text);
    content_type = std::move(type);
  }
  void set_header(std::string name, std::string value) { headers.emplace_back(std::move(name), std::move(value)); }
  bool has_header(std::string_view name) const;
};

using Handler = std::function<void(const Request&, Response&)>;

}  // namespace granulab::server::http
