// Sweeps over HTTP on a real daemon: expansion (product and zip), every point validated before any job
// exists, the sweep's view of its jobs, cancel, quota and rights.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "api/runner.h"
#include "api/spec.h"
#include "tests/server/daemon_fixture.h"

namespace granulab::server {
namespace {

using nlohmann::json;

const json kBase = json::parse(R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
  "loading": {"rate_number": 1e-3}, "output": {"curve_points": 5}})");

json sweep(const json& vary, const std::string& mode = "product") {
  return {{"spec", kBase}, {"vary", vary}, {"mode", mode}, {"label", "study"}};
}

TEST_F(Daemon, ProductSweepRunsEveryCombinationAsOrdinaryJobs) {
  pool_->start();
  const json created =
      post("/v1/sweeps",
           sweep(json::parse(R"({"material.friction": [0.0, 0.3], "loading.prestrain": [0.005, 0.01]})")).dump(), 201);
  ASSERT_EQ(created["jobs"].size(), 4u);
  const std::int64_t id = created["id"];
  for (const json& job : created["jobs"]) EXPECT_EQ(wait(job.get<std::int64_t>())["status"], "succeeded");
  const json view = get("/v1/sweeps/" + std::to_string(id));
  EXPECT_EQ(view["counts"]["succeeded"], 4);
  EXPECT_EQ(view["label"], "study");
  std::set<std::pair<double, double>> points;
  for (const json& j : view["jobs"])
    points.insert({j["values"]["material.friction"].get<double>(), j["values"]["loading.prestrain"].get<double>()});
  EXPECT_EQ(points, (std::set<std::pair<double, double>>{{0.0, 0.005}, {0.0, 0.01}, {0.3, 0.005}, {0.3, 0.01}}));
  // Each job is an ordinary job of the generated spec: its curve is a direct run's.
  const json first = view["jobs"][0];
  const json job = get("/v1/jobs/" + std::to_string(first["id"].get<std::int64_t>()));
  EXPECT_EQ(job["sweep_id"], id);
  EXPECT_EQ(job["spec"]["material"]["friction"], first["values"]["material.friction"]);
  json spec = kBase;
  spec["material"]["friction"] = first["values"]["material.friction"];
  spec["loading"]["prestrain"] = first["values"]["loading.prestrain"];
  auto csv =
      client_->Get(("/v1/jobs/" + std::to_string(first["id"].get<std::int64_t>()) + "/curve?format=csv").c_str());
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->body, api::run_spec(api::parse_spec(spec)).curve_csv);
  EXPECT_EQ(get("/v1/sweeps")["sweeps"][0]["id"], id);
}

TEST_F(Daemon, ZipSweepPairsTheLists) {
  const json created =
      post("/v1/sweeps",
           sweep(json::parse(R"({"material.friction": [0.1, 0.2, 0.3], "loading.max_slide": [0.5, 0.6, 0.7]})"), "zip")
               .dump(),
           201);
  ASSERT_EQ(created["jobs"].size(), 3u);
  const json view = get("/v1/sweeps/" + std::to_string(created["id"].get<std::int64_t>()));
  for (const json& j : view["jobs"])
    EXPECT_NEAR(j["values"]["loading.max_slide"].get<double>() - j["values"]["material.friction"].get<double>(), 0.4,
                1e-12);
}

// Every generated spec is validated first: a bad one is a 400 naming the varied key and its value, and
// no job of the sweep exists.
TEST_F(Daemon, ABadPointRefusesTheWholeSweep) {
  struct Case {
    json request;
    std::string field, words;
  };
  const std::vector<Case> cases = {
      {sweep(json::parse(R"({"material.friction": [0.3, -1.0]})")), "vary.material.friction", "-1"},
      {sweep(json::parse(R"({"grain.bogus": [1]})")), "vary.grain.bogus", "unknown field"},
      // Keys are taken in alphabetical order: the second list is the one that differs.
      {sweep(json::parse(R"({"material.friction": [0.1, 0.2], "loading.max_slide": [0.5]})"), "zip"),
       "vary.material.friction", "as long"},
      {sweep(json::object()), "vary", "must be an object"},
      {sweep(json::parse(R"({"material.friction": []})")), "vary.material.friction", "non-empty list"},
      {sweep(json::parse(R"({"material.friction": 0.3})")), "vary.material.friction", "list"},
      {sweep(json::parse(R"({"experiment": ["crystal_compression"]})")), "vary.experiment", "not the experiment"},
      {sweep(json::parse(R"({"material.friction": [0.3]})"), "diagonal"), "mode", "product"},
      {json::parse(R"({"spec": {"grain": {"size": -1}}, "vary": {"material.friction": [0.3]}})"), "spec.grain.size",
       "base spec"},
      {json::parse(R"({"vary": {"material.friction": [0.3]}, "extra": 1})"), "extra", "unknown field"},
  };
  for (const Case& c : cases) {
    const json e = post("/v1/sweeps", c.request.dump(), 400);
    EXPECT_EQ(e["error"]["field"], c.field) << c.request.dump();
    EXPECT_NE(e["error"]["message"].get<std::string>().find(c.words), std::string::npos) << e.dump();
  }
  EXPECT_TRUE(get("/v1/jobs")["jobs"].empty());
  EXPECT_TRUE(get("/v1/sweeps")["sweeps"].empty());
  // Too many points.
  HttpOptions options;
  options.max_jobs_per_sweep = 5;
  restart(options);
  const json e = post(
      "/v1/sweeps",
      sweep(json::parse(R"({"material.friction": [0.1, 0.2, 0.3], "loading.max_slide": [0.5, 0.6]})")).dump(), 400);
  EXPECT_NE(e["error"]["message"].get<std::string>().find("max_jobs_per_sweep"), std::string::npos);
  get("/v1/sweeps/12345", 404);
}

TEST_F(Daemon, CancellingASweepCancelsWhatHasNotFinished) {
  pool_->start();
  json slow = kBase;
  slow["loading"]["rate_number"] = 1e-8;
  slow["output"]["curve_points"] = 1;
  const json created =
      post("/v1/sweeps",
           json{{"spec", slow}, {"vary", json::parse(R"({"material.friction": [0.1, 0.2, 0.3]})")}}.dump(), 201);
  const std::string path = "/v1/sweeps/" + std::to_string(created["id"].get<std::int64_t>());
  for (int k = 0; k < 500 && get(path)["counts"].value("running", 0) == 0; ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const json r = post(path + "/cancel", "", 200);
  EXPECT_EQ(r["cancelled"], 2);         // the queued two
  EXPECT_EQ(r["cancel_requested"], 1);  // the running one
  for (const json& job : created["jobs"]) EXPECT_EQ(wait(job.get<std::int64_t>(), 5)["status"], "cancelled");
  EXPECT_EQ(get(path)["counts"]["cancelled"], 3);
}

TEST_F(Daemon, SweepsCountAgainstTheQueueQuotaAndBelongToTheirOwner) {
  const auto tokens = dir_ / "tokens";
  std::ofstream(tokens) << "alice a\nbob b\n";
  HttpOptions options;
  options.tokens = read_token_file(tokens.string());
  options.max_queued_per_user = 3;
  restart(options);
  client_->set_bearer_token_auth("a");
  const json refused =
      post("/v1/sweeps", sweep(json::parse(R"({"material.friction": [0.1, 0.2, 0.3, 0.4]})")).dump(), 429);
  EXPECT_NE(refused["error"]["message"].get<std::string>().find("max_queued_per_user"), std::string::npos);
  EXPECT_TRUE(get("/v1/jobs")["jobs"].empty());
  const std::int64_t id =
      post("/v1/sweeps", sweep(json::parse(R"({"material.friction": [0.1, 0.2]})")).dump(), 201)["id"];
  EXPECT_EQ(get("/v1/sweeps/" + std::to_string(id))["owner"], "alice");
  client_->set_bearer_token_auth("b");
  EXPECT_EQ(post("/v1/sweeps/" + std::to_string(id) + "/cancel", "", 403)["error"]["code"], "forbidden");
  get("/v1/sweeps/" + std::to_string(id), 200);  // reading is lab-wide
}

}  // namespace
}  // namespace granulab::server
