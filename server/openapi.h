// The OpenAPI 3.1 document of the HTTP API (GET /v1/openapi.json): docs/openapi.json as compiled in,
// with this build's engine version and the spec schemas generated from the experiment registry.
#pragma once

#include <nlohmann/json.hpp>

namespace granulab::server {

nlohmann::json openapi_document();

}  // namespace granulab::server
