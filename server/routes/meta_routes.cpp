// The routes about the server itself (docs/api.md): its health for monitors, the API document, and the
// registered experiments with their spec fields and curve columns.
#include "api/engine_version.h"
#include "api/spec_docs.h"
#include "server/http/replies.h"
#include "server/openapi.h"
#include "server/routes/routes.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

void mount_meta_routes(Router& router, const RouteContext& c) {
  router.get("/v1/health", {}, [c](const http::Request&, http::Response& res) {
    reply(res, 200,
          {{"status", "ok"},
           {"engine_version", api::engine_version()},
           {api::status_name(JobStatus::queued), c.store.count(JobStatus::queued)},
           {api::status_name(JobStatus::running), c.store.count(JobStatus::running)},
           {"workers", c.executor.workers()},
           {"threads_per_job", c.executor.threads_per_job()},
           {"executor", c.executor.name()}});
  });

  // The API described (OpenAPI 3.1): built once, the registry does not change at run time.
  router.get("/v1/openapi.json", {}, [](const http::Request&, http::Response& res) {
    static const std::string document = openapi_document().dump(1) + "\n";
    res.set_content(document, "application/json");
  });

  // Every registered experiment: its spec fields (default, range, unit, meaning) and curve columns.
  router.get("/v1/experiments", {}, [](const http::Request&, http::Response& res) {
    static const json description = api::experiments_json();  // the registry does not change at run time
    reply(res, 200, description);
  });
}

}  // namespace granulab::server
