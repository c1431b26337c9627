// The route table: what a route group mounts (method, path pattern, the query parameters it takes, the
// handler) and the one dispatch every request goes through. It knows nothing of sockets or of the HTTP
// library, so a group can be mounted alone and called in a test, and the API document's test reads the
// routes from here rather than from the sources.
#pragma once

#include <regex>
#include <string>
#include <vector>

#include "server/http/message.h"

namespace granulab::server::http {

class Router {
 public:
  struct Route {
    std::string method;               ///< GET, POST or DELETE
    std::string pattern;              ///< an ECMAScript regex matched against the whole path, e.g. /v1/jobs/(\d+)
    std::vector<std::string> params;  ///< the query parameters it takes; any other is a 400 naming it
    Handler handler;
    std::regex regex;
    bool any_query = false;  ///< a file: a browser's cache-busting `?v=2` is not a typo
  };
  /// Answers a request before any route (the access rule): true when it answered.
  using Gate = std::function<bool(const Request&, Response&)>;

  void get(const std::string& pattern, std::vector<std::string> params, Handler handler);
  void post(const std::string& pattern, std::vector<std::string> params, Handler handler);
  void del(const std::string& pattern, std::vector<std::string> params, Handler handler);
  /// A GET of a static file, which takes any query parameters and ignores them.
  void file(const std::string& path, Handler handler);
  void set_gate(Gate gate) { gate_ = std::move(gate); }

  /// The gate, then the first route whose method and pattern match (HEAD as GET): fills req.matches,
  /// answers unknown query parameters with a 400, else calls the handler. A path no route matches is a
  /// 404. Handlers may throw; the transport turns that into a 500 (or 507 for a full store).
  void dispatch(Request& req, Response& res) const;

  const std::vector<Route>& routes() const { return routes_; }

 private:
  void add(const char* method, const std::string& pattern, std::vector<std::string> params, Handler handler);
  std::vector<Route> routes_;
  Gate gate_;
};

}  // namespace granulab::server::http
