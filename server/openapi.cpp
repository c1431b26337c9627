#include "server/openapi.h"

#include "api/engine_version.h"
#include "api/spec_docs.h"
#include "server/embedded_files.h"

namespace granulab::server {

nlohmann::json openapi_document() {
  const auto text = embedded_file("docs/openapi.json");
  nlohmann::json doc = text ? nlohmann::json::parse(*text, nullptr, false) : nlohmann::json();
  if (!doc.is_object())
    doc = {{"openapi", "3.1.0"}, {"info", {{"title", "granulab"}}}, {"paths", nlohmann::json::object()}};
  doc["info"]["version"] = api::engine_version();
  // The file holds these too (a test keeps them equal); the registry is what this build accepts.
  const nlohmann::json schemas = api::spec_schemas_json();  // named: items() of a temporary would dangle
  for (const auto& [name, schema] : schemas.items()) doc["components"]["schemas"][name] = schema;
  return doc;
}

}  // namespace granulab::server
