#include "server/http/router.h"

#include <algorithm>

#include "server/http/replies.h"

namespace granulab::server::http {

void Router::add(const char* method, const std::string& pattern, std::vector<std::string> params, Handler handler) {
  routes_.push_back({method, pattern, std::move(params), std::move(handler), std::regex(pattern)});
}

void Router::get(const std::string& pattern, std::vector<std::string> params, Handler handler) {
  add("GET", pattern, std::move(params), std::move(handler));
}
void Router::post(const std::string& pattern, std::vector<std::string> params, Handler handler) {
  add("POST", pattern, std::move(params), std::move(handler));
}
void Router::del(const std::string& pattern, std::vector<std::string> params, Handler handler) {
  add("DELETE", pattern, std::move(params), std::move(handler));
}

void Router::file(const std::string& path, Handler handler) {
  add("GET", path, {}, std::move(handler));
  routes_.back().any_query = true;
}

void Router::dispatch(Request& req, Response& res) const {
  if (gate_ && gate_(req, res)) return;
  const std::string& method = req.method == "HEAD" ? std::string("GET") : req.method;
  for (const Route& route : routes_) {
    std::smatch match;
    if (route.method != method || !std::regex_match(req.path, match, route.regex)) continue;
    req.matches.assign(match.begin(), match.end());
    // Only the query parameters a route knows: `?resue=true` is a typo to report, not to ignore.
    for (const auto& [name, value] : req.query) {
      if (route.any_query) break;
      if (std::find(route.params.begin(), route.params.end(), name) != route.params.end()) continue;
      std::string list;
      for (const std::string& k : route.params) list += (list.empty() ? "" : ", ") + k;
      return error(res, 400, "unknown_parameter",
                   "unknown query parameter '" + name + "' (" +
                       (route.params.empty() ? std::string("this route takes none") : "this route takes: " + list) +
                       ")",
                   name);
    }
    return route.handler(req, res);
  }
  error(res, 404, "not_found", "no such route");
}

}  // namespace granulab::server::http
