// The API document (docs/openapi.json, served at GET /v1/openapi.json) describes the server that exists:
// every route the server's sources register is in it with the same method and exactly the query
// parameters the route accepts, nothing in it is a route that does not exist, the spec schemas are the
// registry's (ranges and defaults), and every example spec uses only fields the schemas name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "api/spec_docs.h"
#include "engine/experiments/registry.h"
#include "server/openapi.h"
#include "tests/server/daemon_fixture.h"

namespace granulab::server {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = GRANULAB_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// "METHOD path" -> query parameters, from the route table granulabd serves (every group mounted).
// A path's (\d+) groups become *, as do the document's {name} templates.
std::map<std::string, std::set<std::string>> registered_routes() {
  JobStore store(":memory:");
  WorkerPool pool(store, 1, 1);
  HttpServer server(store, pool);
  mount_every_route(server);
  std::map<std::string, std::set<std::string>> routes;
  for (const http::Router::Route& r : server.router().routes()) {
    std::string path = std::regex_replace(r.pattern, std::regex(R"(\(\\d\+\))"), "*");
    path = std::regex_replace(path, std::regex(R"(\\\.)"), ".");
    routes[r.method + " " + path] = std::set<std::string>(r.params.begin(), r.params.end());
  }
  return routes;
}

std::map<std::string, std::set<std::string>> documented_routes(const nlohmann::json& doc) {
  std::map<std::string, std::set<std::string>> routes;
  for (const auto& [path, item] : doc["paths"].items())
    for (const auto& [method, operation] : item.items()) {
      std::string m = method;
      for (char& c : m) c = char(std::toupper(c));
      std::set<std::string> params;
      for (const auto& p : operation.value("parameters", nlohmann::json::array()))
        if (p["in"] == "query") params.insert(p["name"].get<std::string>());
      routes[m + " " + std::regex_replace(path, std::regex(R"(\{[a-z_]+\})"), "*")] = params;
    }
  return routes;
}

TEST(OpenApi, EveryRegisteredRouteIsDocumentedWithItsQueryParametersAndNoOtherRouteIs) {
  const auto registered = registered_routes();
  ASSERT_GE(registered.size(), 20u);
  const auto documented = documented_routes(openapi_document());
  for (const auto& [route, params] : registered) {
    const auto it = documented.find(route);
    if (it == documented.end()) {
      ADD_FAILURE() << route << " is served but not in docs/openapi.json";
      continue;
    }
    EXPECT_EQ(it->second, params) << route << ": the document's query parameters differ from the route's";
  }
  for (const auto& [route, params] : documented)
    EXPECT_TRUE(registered.count(route)) << route << " is documented but not served";
}

// Client generators name a method after its operation's operationId (openapi-typescript, openapi-generator): every
// operation has one, unique in the document, and usable as an identifier.
TEST(OpenApi, EveryOperationHasAUniqueOperationId) {
  const nlohmann::json doc = openapi_document();
  std::set<std::string> seen;
  std::size_t operations = 0;
  for (const auto& [path, item] : doc["paths"].items())
    for (const auto& [method, op] : item.items()) {
      if (method != "get" && method != "post" && method != "put" && method != "delete" && method != "patch") continue;
      ++operations;
      ASSERT_TRUE(op.contains("operationId") && op["operationId"].is_string()) << method << " " << path;
      const std::string id = op["operationId"];
      EXPECT_TRUE(std::regex_match(id, std::regex("[a-z][A-Za-z0-9]*"))) << id;
      EXPECT_TRUE(seen.insert(id).second) << id << " names two operations";
    }
  EXPECT_GE(operations, 30u);
}

TEST(OpenApi, TheFileInTheRepositoryIsTheServedDocument) {
  // Only the version differs (it is the build's). On a failure after a spec field changed:
  //   cp build/openapi.json docs/openapi.json
  nlohmann::json served = openapi_document(), file = nlohmann::json::parse(read(kSource / "docs" / "openapi.json"));
  served["info"]["version"] = file["info"]["version"];
  if (served != file) {
    std::ofstream(fs::path(GRANULAB_BINARY_DIR) / "openapi.json") << served.dump(1, ' ', false) << "\n";
    FAIL() << "docs/openapi.json differs from what the server serves; the served one is in build/openapi.json";
  }
  EXPECT_EQ(file["openapi"], "3.1.0");
}

// Every key of every example is a property of its experiment's schema (and the default of a field is
// within its own bounds): a renamed or removed field fails here before it confuses a client generator.
void expect_known(const nlohmann::json& value, const nlohmann::json& schema, const std::string& where) {
  if (!value.is_object()) return;
  const auto& properties = schema.contains("properties") ? schema["properties"] : nlohmann::json::object();
  for (const auto& [key, v] : value.items()) {
    ASSERT_TRUE(properties.contains(key)) << where << key << " is not in the schema";
    const auto& s = properties[key];
    if (v.is_array() && s.contains("items")) {
      for (const auto& item : v) expect_known(item, s["items"], where + key + "[].");
    } else {
      expect_known(v, s, where + key + ".");
    }
    if (v.is_number() && s.contains("maximum")) EXPECT_LE(v.get<double>(), s["maximum"].get<double>()) << where << key;
    if (v.is_number() && s.contains("minimum")) EXPECT_GE(v.get<double>(), s["minimum"].get<double>()) << where << key;
  }
}

TEST(OpenApi, EveryExampleSpecUsesOnlyDocumentedFieldsWithinTheirRanges) {
  const nlohmann::json schemas = api::spec_schemas_json();
  int examples = 0;
  for (const auto& entry : fs::directory_iterator(kSource / "examples")) {
    if (entry.path().extension() != ".json") continue;
    const nlohmann::json spec = nlohmann::json::parse(read(entry.path()));
    const std::string schema = "Spec_" + spec.value("experiment", std::string("two_cube_sliding"));
    ASSERT_TRUE(schemas.contains(schema)) << entry.path();
    expect_known(spec, schemas[schema], entry.path().filename().string() + ": ");
    ++examples;
  }
  EXPECT_GE(examples, 10);
}

TEST_F(Daemon, ServesTheApiDocumentWithTheEngineVersion) {
  const nlohmann::json doc = get("/v1/openapi.json");
  EXPECT_EQ(doc["info"]["version"], get("/v1/health")["engine_version"]);
  EXPECT_TRUE(doc["paths"].contains("/v1/jobs/{id}/snapshots/{k}.svg"));
  EXPECT_EQ(doc["components"]["schemas"]["Spec"]["oneOf"].size(), experiment_types().size());
}

}  // namespace
}  // namespace granulab::server
