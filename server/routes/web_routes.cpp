// The web page (GET /, docs/api.md "Web page") and the example specs its submit form starts from
// (GET /v1/examples), both compiled into the daemon (server/embedded_files.h).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "api/spec.h"
#include "server/embedded_files.h"
#include "server/routes/routes.h"
#include "server/http/replies.h"
#include "server/job_views.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

void mount_web_routes(Router& router, const RouteContext&) {
  // One embedded file per route.
  const auto file = [](const char* name, const char* type) {
    return [name, type](const http::Request&, http::Response& res) {
      const auto text = embedded_file(name);
      if (!text) return error(res, 404, "not_found", std::string("this build has no ") + name);
      res.set_content(std::string(*text), type);
      // The page is part of the binary: a browser revalidates it rather than keeping an old daemon's.
      res.set_header("Cache-Control", "no-cache");
    };
  };
  router.file("/", file("server/web/index.html", "text/html; charset=utf-8"));
  router.file("/web/app\\.js", file("server/web/app.js", "text/javascript; charset=utf-8"));
  router.file("/web/style\\.css", file("server/web/style.css", "text/css; charset=utf-8"));

  // The specs of examples/ (the paper's experiments), by name: what the submit form is prefilled from. The
  // cheapest first (expected sphere-steps), so that the form's first choice is a quick run, not hours.
  router.get("/v1/examples", {}, [](const http::Request&, http::Response& res) {
    static const json examples = [] {
      std::vector<std::pair<double, json>> found;
      for (std::string_view name : embedded_names()) {
        const std::string prefix = "examples/", suffix = ".json";
        if (name.substr(0, prefix.size()) != prefix) continue;
        const std::string text(*embedded_file(name));
        const json spec = json::parse(text, nullptr, false);
        if (!spec.is_object()) continue;
        double cost = 1e300;  // an example this build does not accept goes last
        try {
          cost = api::parse_spec_text(text).experiment->workload().expected_sphere_steps();
        } catch (const std::exception&) {}
        found.push_back(
            {cost,
             {{"name", std::string(name.substr(prefix.size(), name.size() - prefix.size() - suffix.size()))},
              {"spec", spec}}});
      }
      std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      json list = json::array();
      for (auto& [cost, example] : found) list.push_back(std::move(example));
      return json{{"examples", list}};
    }();
    reply(res, 200, examples);
  });
}

}  // namespace granulab::server
