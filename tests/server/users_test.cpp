// Users on a shared server: tokens with roles, who may read and who may change which job, quotas.
// The access matrix runs every route against every kind of caller on a real daemon.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/server/daemon_fixture.h"

namespace granulab::server {
namespace {

using nlohmann::json;

const char* kSpec = R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
  "loading": {"rate_number": 1e-3}, "output": {"curve_points": 10}})";

enum class Caller { none, wrong, other, owner, admin };
const char* name(Caller c) {
  switch (c) {
    case Caller::none: return "no token";
    case Caller::wrong: return "wrong token";
    case Caller::other: return "other user";
    case Caller::owner: return "owner";
    case Caller::admin: return "admin";
  }
  return "";
}

class Users : public Daemon {
 protected:
  void SetUp() override {
    Daemon::SetUp();
    tokens_ = dir_ / "tokens";
    std::ofstream(tokens_) << "alice tok-alice\nbob tok-bob\nroot tok-root admin\n";
  }
  void serve(bool private_reads, int max_queued = 1000) {
    HttpOptions options;
    options.tokens = read_token_file(tokens_.string());
    options.private_reads = private_reads;
    options.max_queued_per_user = max_queued;
    restart(options);
  }
  // The status of one request as `who` (alice owns the jobs).
  int as(Caller who, const std::string& method, const std::string& path, const std::string& body = "") {
    httplib::Headers headers;
    const std::map<Caller, std::string> token = {{Caller::wrong, "tok-mallory"},
                                                 {Caller::other, "tok-bob"},
                                                 {Caller::owner, "tok-alice"},
                                                 {Caller::admin, "tok-root"}};
    if (who != Caller::none) headers.emplace("Authorization", "Bearer " + token.at(who));
    httplib::Result r = method == "GET"      ? client_->Get(path.c_str(), headers)
                        : method == "DELETE" ? client_->Delete(path.c_str(), headers)
                                             : client_->Post(path.c_str(), headers, body, "application/json");
    if (!r) return -1;
    if (r->status >= 400) {  // every refusal says why, in the usual shape
      const json e = json::parse(r->body, nullptr, false);
      EXPECT_TRUE(e.contains("error") && !e["error"]["message"].get<std::string>().empty()) << r->body;
    }
    return r->status;
  }
  std::int64_t submit_as_alice() {
    client_->set_bearer_token_auth("tok-alice");
    const std::int64_t id = post("/v1/jobs", kSpec, 201)["id"];
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    return id;
  }
  std::int64_t finished_job() {
    client_->set_bearer_token_auth("tok-root");
    pool_->start();
    const std::int64_t id = submit_as_alice();
    client_->set_bearer_token_auth("tok-root");
    EXPECT_EQ(wait(id)["status"], "succeeded");
    pool_->stop();
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    return id;
  }
  std::filesystem::path tokens_;
};

// Every route x every caller, lab-wide reads: reading is for every user, changing a job for its owner
// and admins (403 for others), and nothing but health without a known token (401).
TEST_F(Users, AccessMatrixLabWide) {
  serve(false);
  const std::int64_t done = finished_job();
  const std::string job = "/v1/jobs/" + std::to_string(done);
  const std::vector<Caller> callers = {Caller::none, Caller::wrong, Caller::other, Caller::owner, Caller::admin};
  for (Caller who : callers) {
    SCOPED_TRACE(name(who));
    const bool known = who != Caller::none && who != Caller::wrong;
    const bool may_change = who == Caller::owner || who == Caller::admin;
    EXPECT_EQ(as(who, "GET", "/v1/health"), 200);
    EXPECT_EQ(as(who, "GET", "/v1/experiments"), known ? 200 : 401);
    EXPECT_EQ(as(who, "GET", "/v1/jobs"), known ? 200 : 401);
    EXPECT_EQ(as(who, "POST", "/v1/jobs", kSpec), known ? 201 : 401);
    for (const std::string& read : {job, job + "/curve", job + "/snapshots", job + "/curve.svg", job + "/archive",
                                    std::string("/v1/openapi.json"), std::string("/v1/examples")})
      EXPECT_EQ(as(who, "GET", read), known ? 200 : 401) << read;
    EXPECT_EQ(as(who, "GET", job + "/snapshots/0"), known ? 404 : 401);  // a two-cube job has none
    EXPECT_EQ(as(who, "GET", job + "/snapshots/0.svg"), known ? 404 : 401);
    for (const char* page : {"/", "/web/app.js", "/web/style.css"})
      EXPECT_EQ(as(who, "GET", page), 200) << page;  // it asks
    // Changes: each on a fresh queued job of alice's.
    const std::string queued = "/v1/jobs/" + std::to_string(submit_as_alice());
    EXPECT_EQ(as(who, "POST", queued + "/priority?value=-5"), !known ? 401 : may_change ? 200 : 403);
    // Above the default is for admins, even on one's own job.
    EXPECT_EQ(as(who, "POST", queued + "/priority?value=5"), !known ? 401 : who == Caller::admin ? 200 : 403);
    EXPECT_EQ(as(who, "POST", queued + "/cancel"), !known ? 401 : may_change ? 200 : 403);
    EXPECT_EQ(as(Caller::owner, "POST", queued + "/cancel"), may_change ? 409 : 200);  // now cancelled either way
    EXPECT_EQ(as(who, "DELETE", queued), !known ? 401 : may_change ? 200 : 403);
  }
  // The finished job itself: others may not delete it, its owner may.
  EXPECT_EQ(as(Caller::other, "DELETE", job), 403);
  EXPECT_EQ(as(Caller::owner, "DELETE", job), 200);
  EXPECT_EQ(as(Caller::admin, "GET", job), 404);
  EXPECT_EQ(as(Caller::admin, "GET", job + "/curve"), 404);
}

// --private: reading a job is for its owner and admins; listings show a user their own jobs.
TEST_F(Users, PrivateServerHidesOthersJobs) {
  serve(true);
  const std::int64_t done = finished_job();
  const std::string job = "/v1/jobs/" + std::to_string(done);
  for (const std::string& read : {job, job + "/curve", job + "/snapshots", job + "/snapshots/0", job + "/curve.svg",
                                  job + "/archive", job + "/snapshots/0.svg", job + "/snapshots/0?format=dump"}) {
    EXPECT_EQ(as(Caller::other, "GET", read), 403) << read;
    EXPECT_NE(as(Caller::owner, "GET", read), 403) << read;
    EXPECT_NE(as(Caller::admin, "GET", read), 403) << read;
  }
  client_->set_bearer_token_auth("tok-bob");
  post("/v1/jobs", kSpec, 201);
  EXPECT_EQ(get("/v1/jobs")["jobs"].size(), 1u);  // bob sees his one job, not alice's
  EXPECT_EQ(get("/v1/jobs?owner=alice", 403)["error"]["field"], "owner");
  client_->set_bearer_token_auth("tok-root");
  EXPECT_EQ(get("/v1/jobs")["jobs"].size(), 2u);
  EXPECT_EQ(get("/v1/jobs?owner=alice")["jobs"].size(), 1u);
  EXPECT_EQ(get("/v1/jobs?owner=alice")["jobs"][0]["owner"], "alice");
}

// ?owner= filters listings on a lab-wide server too.
TEST_F(Users, ListingsFilterByOwner) {
  serve(false);
  submit_as_alice();
  submit_as_alice();
  client_->set_bearer_token_auth("tok-bob");
  post("/v1/jobs", kSpec, 201);
  EXPECT_EQ(get("/v1/jobs")["jobs"].size(), 3u);
  EXPECT_EQ(get("/v1/jobs?owner=alice")["jobs"].size(), 2u);
  EXPECT_EQ(get("/v1/jobs?owner=bob&status=queued")["jobs"].size(), 1u);
  EXPECT_TRUE(get("/v1/jobs?owner=nobody")["jobs"].empty());
}

// --max-queued-per-user: one user's flood is refused with 429 naming the limit; others still submit.
TEST_F(Users, QueuedQuotaIsPerUser) {
  serve(false, 2);
  submit_as_alice();
  submit_as_alice();
  client_->set_bearer_token_auth("tok-alice");
  const json refused = post("/v1/jobs", kSpec, 429);
  EXPECT_EQ(refused["error"]["code"], "quota");
  EXPECT_NE(refused["error"]["message"].get<std::string>().find("max_queued_per_user"), std::string::npos);
  client_->set_bearer_token_auth("tok-bob");
  post("/v1/jobs", kSpec, 201);
}

// --max-memory and --max-sphere-steps: a job over either is refused at submission, with the estimate
// and the limit in the message; one under both is accepted.
TEST_F(Users, BudgetIsCheckedBeforeAJobIsAccepted) {
  HttpOptions options;
  options.max_memory_bytes = 100e6;
  options.max_sphere_steps = 1e9;
  restart(options);
  // 40 x 100 x 10 grains of 50 spheres: 2e6 spheres, about 0.3 GB by the measured model.
  const char* big = R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
    "crystal": {"grains_x": 40, "rows_z": 100, "layers_y": 10}})";
  json refused = post("/v1/jobs", big, 400);
  EXPECT_EQ(refused["error"]["code"], "over_budget");
  std::string message = refused["error"]["message"];
  EXPECT_NE(message.find("max_memory"), std::string::npos) << message;
  EXPECT_NE(message.find("0.10 GB"), std::string::npos) << message;        // the limit
  EXPECT_NE(message.find("2e+06 spheres"), std::string::npos) << message;  // the estimate's basis
  // Small, but 4e8 steps of 52 spheres (rate_number 1e-8) = 2e10 sphere-steps > 1e9.
  refused = post("/v1/jobs", R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
    "loading": {"rate_number": 1e-8}})",
                 400);
  message = refused["error"]["message"];
  EXPECT_NE(message.find("max_sphere_steps"), std::string::npos) << message;
  post("/v1/jobs", kSpec, 201);
}

std::filesystem::path write(const std::filesystem::path& p, const std::string& text, mode_t mode) {
  std::ofstream(p) << text;
  ::chmod(p.c_str(), mode);
  return p;
}

TEST_F(Users, TokenFileRules) {
  const auto p = dir_ / "t";
  std::string warning;
  auto tokens = read_token_file(write(p, "alice a1\nroot r1 admin\n", 0600).string(), &warning);
  EXPECT_TRUE(warning.empty()) << warning;
  // Kept by hash: the file's plain tokens are hashed as they are read, and a hash in the file is kept as is.
  EXPECT_FALSE(tokens.count("a1"));
  EXPECT_FALSE(tokens.at(token_hash("a1")).admin);
  EXPECT_TRUE(tokens.at(token_hash("r1")).admin);
  EXPECT_EQ(tokens.at(token_hash("r1")).name, "root");
  EXPECT_EQ(token_hash("a1").size(), 7u + 64u);
  tokens = read_token_file(write(p, "alice " + token_hash("a1") + "\n", 0600).string());
  EXPECT_EQ(tokens.at(token_hash("a1")).name, "alice");
  // The same token written plain and hashed is one token given twice.
  EXPECT_THROW(read_token_file(write(p, "alice a1\nbob " + token_hash("a1") + "\n", 0600).string()),
               std::invalid_argument);
  read_token_file(write(p, "alice a1\n", 0644).string(), &warning);
  EXPECT_NE(warning.find("readable by other users"), std::string::npos);
  // One token per user, one user per token, known roles only: start-up errors naming the line.
  for (const char* bad :
       {"alice same\nbob same\n", "alice a1\nalice a2\n", "alice a1 owner\n", "alice\n", "# only\n"}) {
    try {
      read_token_file(write(p, bad, 0600).string());
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace granulab::server
