// A route group is a peer that stands alone: mounted by itself on a Router with a store, access rules
// and admission checks, it answers requests dispatched to it directly (no socket, no transport, no
// other group), and what it does lands in the store.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "server/access.h"
#include "server/admission.h"
#include "server/http/router.h"
#include "server/routes/routes.h"
#include "server/store/job_store.h"
#include "server/worker_secrets.h"

namespace granulab::server {
namespace {

using nlohmann::json;

// Counts what the routes tell the executor; runs nothing.
struct CountingExecutor : Executor {
  void start() override {}
  void stop() override {}
  void notify() override { ++notified; }
  void cancel_requested(std::int64_t) override { ++cancels; }
  std::string name() const override { return "counting"; }
  int workers() const override { return 0; }
  int threads_per_job() const override { return 1; }
  double checkpoint_seconds() const override { return 0; }
  int notified = 0, cancels = 0;
};

struct OneGroup : ::testing::Test {
  JobStore store{":memory:"};
  CountingExecutor executor;
  Access access{{{"t-ann", User{"ann", false}}, {"t-bob", User{"bob", false}}}, false};
  Admission admission{store, executor, {3, 0, 1e13}};
  WorkerSecrets secrets{store};
  RouteContext context{store, executor, access, admission, secrets, 10};
  http::Router router;

  json call(const std::string& method, const std::string& target, const std::string& body, const std::string& token,
            int expected) {
    http::Request req(body);
    req.method = method;
    req.target = target;
    const auto mark = target.find('?');
    req.path = target.substr(0, mark);
    if (mark != std::string::npos) {
      const std::string query = target.substr(mark + 1);
      req.query.emplace_back(query.substr(0, query.find('=')), query.substr(query.find('=') + 1));
    }
    req.headers.emplace_back("authorization", "Bearer " + token);  // header names are case-insensitive
    http::Response res;
    router.dispatch(req, res);
    EXPECT_EQ(res.status, expected) << method << " " << target << ": " << res.body;
    return json::parse(res.body, nullptr, false);
  }
};

const std::string kSweep = R"({"spec": {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3}},
                               "vary": {"material.friction": [0.1, 0.2]}, "label": "alone"})";

TEST_F(OneGroup, TheSweepRoutesAloneCreateListAndCancelSweepsInTheStore) {
  router.set_gate([this](const http::Request& req, http::Response& res) { return access.gate(req, res); });
  mount_sweep_routes(router, context);
  const json created = call("POST", "/v1/sweeps", kSweep, "t-ann", 201);
  ASSERT_EQ(created["jobs"].size(), 2u);
  EXPECT_EQ(store.count(JobStatus::queued, "ann"), 2u);
  EXPECT_EQ(executor.notified, 1);
  const std::string path = "/v1/sweeps/" + std::to_string(created["id"].get<std::int64_t>());
  EXPECT_EQ(call("GET", path, "", "t-bob", 200)["counts"]["queued"], 2);
  // The access rule and the admission check come with the context, not with the daemon.
  EXPECT_EQ(call("POST", path + "/cancel", "", "t-bob", 403)["error"]["code"], "forbidden");
  EXPECT_EQ(call("POST", "/v1/sweeps", kSweep, "t-ann", 429)["error"]["code"], "quota");  // 2 + 2 > 3
  EXPECT_EQ(call("GET", "/v1/sweeps", "", "nobody", 401)["error"]["code"], "unauthorized");
  EXPECT_EQ(call("GET", "/v1/sweeps?bogus=1", "", "t-ann", 400)["error"]["field"], "bogus");
  EXPECT_EQ(call("POST", path + "/cancel", "", "t-ann", 200)["cancelled"], 2);
  EXPECT_EQ(store.count(JobStatus::cancelled, "ann"), 2u);
  EXPECT_EQ(executor.cancels, 2);
  // No other group is there: the job routes were not mounted.
  EXPECT_EQ(call("GET", "/v1/jobs", "", "t-ann", 404)["error"]["message"], "no such route");
}

}  // namespace
}  // namespace granulab::server
