// The daemon's HTTP API end to end: a real SQLite file, a worker pool, the routes on 127.0.0.1 (any
// free port) and cpp-httplib's client. Results served over HTTP must equal the engine's own for the
// same spec, and bad requests get their documented status and a message naming the field.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <tuple>
#include <algorithm>
#include <atomic>
#include <mutex>
#include <regex>

#include <nlohmann/json.hpp>

#include "api/engine_version.h"
#include "engine/contact/pair_kernel.h"
#include "api/runner.h"
#include "server/http_server.h"
#include "server/worker_pool.h"
#include "tests/server/daemon_fixture.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::server {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const char* kTwoCube = R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
  "loading": {"rate_number": 1e-3}, "output": {"curve_points": 10}})";
const char* kCrystal = R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
  "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
  "loading": {"confining_pressure": 30e3, "max_strain": 2e-4},
  "output": {"curve_points": 8, "snapshot_strains": [0.0, 2e-4]}})";

TEST_F(Daemon, TwoCubeJobGivesTheEnginesOwnCurve) {
  pool_->start();
  const json health = get("/v1/health");
  EXPECT_EQ(health["status"], "ok");
  const json created = post("/v1/jobs", kTwoCube, 201);
  ASSERT_EQ(created["status"], "queued");
  const std::int64_t id = created["id"];
  const json done = wait(id);
  ASSERT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_DOUBLE_EQ(done["progress"].get<double>(), 1.0);
  EXPECT_EQ(done["summary"]["spheres"], 2 * (6 + 12 + 8));

  // The same spec run directly: the engine is deterministic, so the served curve is identical.
  const api::RunOutput direct = api::run_spec(api::parse_spec_text(kTwoCube));
  auto csv = client_->Get(("/v1/jobs/" + std::to_string(id) + "/curve?format=csv").c_str());
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->status, 200);
  EXPECT_EQ(csv->body, direct.curve_csv);
  const json curve = get("/v1/jobs/" + std::to_string(id) + "/curve");
  EXPECT_EQ(curve["columns"][0], "slide_over_size");
  EXPECT_EQ(curve["normal_over_p0"].size(), 11u);
  EXPECT_DOUBLE_EQ(curve["normal_over_p0"][0].get<double>(), 1.0);

  const json list = get("/v1/jobs?status=succeeded");
  ASSERT_EQ(list["jobs"].size(), 1u);
  EXPECT_EQ(list["jobs"][0]["id"], id);
  // Identical spec with reuse: the stored result, no new job.
  const json reused = post("/v1/jobs?reuse=true", kTwoCube, 200);
  EXPECT_EQ(reused["id"], id);
  EXPECT_TRUE(reused["reused"].get<bool>());
}

TEST_F(Daemon, CrystalJobStoresSnapshots) {
  pool_->start();
  const std::int64_t id = post("/v1/jobs", kCrystal, 201)["id"];
  const json done = wait(id);
  ASSERT_EQ(done["status"], "succeeded") << done.dump();
  const json snaps = get("/v1/jobs/" + std::to_string(id) + "/snapshots");
  ASSERT_EQ(snaps["snapshots"].size(), 2u);
  const json s1 = get("/v1/jobs/" + std::to_string(id) + "/snapshots/1");
  EXPECT_EQ(s1["grains"]["id"].size(), 16u);
  EXPECT_NEAR(s1["strain"].get<double>(), 2e-4, 1e-12);
  get("/v1/jobs/" + std::to_string(id) + "/snapshots/7", 404);
  // 2^32 and 2^32 + 1 are not snapshots 0 and 1 (an index cast to 32 bits would wrap onto them).
  get("/v1/jobs/" + std::to_string(id) + "/snapshots/4294967296", 404);
  get("/v1/jobs/" + std::to_string(id) + "/snapshots/4294967297", 404);
  // The same as running the spec directly (the engine gives the same answer for any thread count).
  const api::RunOutput direct = api::run_spec(api::parse_spec_text(kCrystal));
  auto csv = client_->Get(("/v1/jobs/" + std::to_string(id) + "/curve?format=csv").c_str());
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->body, direct.curve_csv);
  ASSERT_EQ(direct.snapshots.size(), 2u);
  EXPECT_EQ(s1, direct.snapshots[1].second);
}

// A job whose run throws becomes `failed` with the message, and the daemon keeps serving.
TEST_F(Daemon, AThrowingJobFailsWithItsMessage) {
  pool_->start();
  // Valid spec, impossible crystal: knocking out both grains of a 2-grain crystal leaves nothing to load.
  const std::int64_t id = post("/v1/jobs", R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
      "crystal": {"grains_x": 2, "rows_z": 1, "layers_y": 1, "knockout": [0, 1]}})",
                               201)["id"];
  const json done = wait(id);
  EXPECT_EQ(done["status"], "failed");
  EXPECT_NE(done["error"].get<std::string>().find("fewer than two grains"), std::string::npos) << done.dump();
  EXPECT_EQ(get("/v1/health")["status"], "ok");
  EXPECT_EQ(post("/v1/jobs", kTwoCube, 201)["status"], "queued");
}

// With the pool not started, jobs stay queued: the state rules can be checked without races.
TEST_F(Daemon, BadRequestsGetTheirDocumentedStatus) {
  struct Case {
    const char* body;
    const char* code;
    const char* field;
  };
  for (const Case& c : {Case{"{not json", "invalid_json", ""},
                        Case{R"({"grain": {"edge_spheres": "ten"}})", "wrong_type", "grain.edge_spheres"},
                        Case{R"({"grain": {"edge_spheres": 1}})", "out_of_range", "grain.edge_spheres"},
                        Case{R"({"experiment": "triaxial"})", "invalid_value", "experiment"},
                        Case{R"({"grain": {"edge_sphere": 4}})", "unknown_field", "grain.edge_sphere"}}) {
    const json e = post("/v1/jobs", c.body, 400);
    EXPECT_EQ(e["error"]["code"], c.code) << c.body;
    EXPECT_EQ(e["error"]["field"], c.field) << c.body;
    EXPECT_FALSE(e["error"]["message"].get<std::string>().empty());
  }
  auto huge = client_->Post("/v1/jobs", std::string(100 * 1024, ' '), "application/json");
  ASSERT_TRUE(huge);
  EXPECT_EQ(huge->status, 413);
  get("/v1/jobs/999", 404);
  get("/v1/jobs?limit=0", 400);
  get("/v1/jobs?status=done", 400);

  const std::int64_t id = post("/v1/jobs", kTwoCube, 201)["id"];
  get("/v1/jobs/" + std::to_string(id) + "/curve", 409);  // queued: no curve yet
  EXPECT_EQ(post("/v1/jobs/" + std::to_string(id) + "/cancel", "", 200)["status"], "cancelled");
  post("/v1/jobs/" + std::to_string(id) + "/cancel", "", 409);  // already finished
  post("/v1/jobs/12345/cancel", "", 404);
  EXPECT_EQ(get("/v1/jobs/" + std::to_string(id))["status"], "cancelled");
  EXPECT_EQ(get("/v1/health")["status"], "ok");  // and the daemon is still up
}

}  // namespace
}  // namespace granulab::server

namespace granulab::server {
namespace {

// 20 jobs from 4 client threads at once with 2 workers: every job runs exactly once and finishes, ids
// are distinct, and never more than 2 run at a time (sampled through /v1/health while they run).
TEST_F(Daemon, TwentyJobsFromFourClientsRunAtMostKAtATime) {
  pool_->stop();
  pool_ = std::make_unique<WorkerPool>(*store_, 2, 1, 0.05);
  http_->stop();
  serving_.join();
  http_ = std::make_unique<HttpServer>(*store_, *pool_, HttpOptions{64 * 1024, 8, {}});
  mount_every_route(*http_);
  port_ = http_->bind("127.0.0.1", 0);
  serving_ = std::thread([this] { http_->serve(); });
  client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
  for (int k = 0; k < 100 && !client_->Get("/v1/health"); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  pool_->start();

  std::vector<std::int64_t> ids;
  std::mutex ids_mutex;
  std::vector<std::thread> clients;
  for (int t = 0; t < 4; ++t)
    clients.emplace_back([&] {
      httplib::Client c("127.0.0.1", port_);
      for (int k = 0; k < 5; ++k) {
        auto r = c.Post("/v1/jobs", kTwoCube, "application/json");
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 201);
        std::lock_guard<std::mutex> lock(ids_mutex);
        ids.push_back(json::parse(r->body)["id"]);
      }
    });
  int max_running = 0;
  std::atomic<bool> sampling{true};
  std::thread sampler([&] {
    httplib::Client c("127.0.0.1", port_);
    while (sampling) {
      if (auto r = c.Get("/v1/health")) max_running = std::max(max_running, json::parse(r->body)["running"].get<int>());
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  for (std::thread& c : clients) c.join();
  ASSERT_EQ(ids.size(), 20u);
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(std::unique(ids.begin(), ids.end()), ids.end());
  for (std::int64_t id : ids) EXPECT_EQ(wait(id)["status"], "succeeded") << id;
  sampling = false;
  sampler.join();
  EXPECT_LE(max_running, 2);
  EXPECT_GE(max_running, 1);
  EXPECT_EQ(get("/v1/jobs?status=succeeded&limit=100")["jobs"].size(), 20u);
}

// With a token file, every route but health needs a known bearer token, and jobs record their owner.
TEST_F(Daemon, TokensGuardEveryRouteButHealth) {
  const fs::path tokens = dir_ / "tokens";
  std::ofstream(tokens) << "# user token\nalice tok-alice\nbob tok-bob\n";
  restart(HttpOptions{64 * 1024, 4, read_token_file(tokens.string())});

  get("/v1/health", 200);
  EXPECT_EQ(get("/v1/jobs", 401)["error"]["code"], "unauthorized");
  post("/v1/jobs", kTwoCube, 401);
  client_->set_bearer_token_auth("tok-mallory");
  get("/v1/jobs", 401);
  client_->set_bearer_token_auth("tok-alice");
  const std::int64_t id = post("/v1/jobs", kTwoCube, 201)["id"];
  EXPECT_EQ(get("/v1/jobs/" + std::to_string(id))["owner"], "alice");
  EXPECT_THROW(read_token_file((dir_ / "missing").string()), std::invalid_argument);
}

// The CLI's remote commands against this daemon: submit, wait, results, list, cancel, status.
std::pair<int, std::string> shell(const std::string& command) {
  std::string output;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

TEST_F(Daemon, CliRemoteCommands) {
  pool_->start();
  const std::string cli = std::string(GRANULAB_BINARY_DIR) + "/granulab";
  const std::string server = " --server http://127.0.0.1:" + std::to_string(port_);
  const fs::path spec = dir_ / "spec.json";
  std::ofstream(spec) << kTwoCube;

  auto [code, out] = shell(cli + " submit " + spec.string() + server);
  ASSERT_EQ(code, 0) << out;
  ASSERT_EQ(out.find_first_not_of("0123456789\n"), std::string::npos) << "submit prints the id alone: " << out;
  const std::int64_t id = std::stoll(out);
  std::tie(code, out) = shell(cli + " wait " + std::to_string(id) + server);
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = shell(cli + " results " + std::to_string(id) + " --out " + (dir_ / "r").string() + server);
  ASSERT_EQ(code, 0) << out;
  std::ifstream curve(dir_ / "r" / "curve.csv");
  std::stringstream text;
  text << curve.rdbuf();
  EXPECT_EQ(text.str(), api::run_spec(api::parse_spec_text(kTwoCube)).curve_csv);
  for (const char* file : {"summary.json", "spec.json", "curve.svg"})
    EXPECT_TRUE(fs::exists(dir_ / "r" / file)) << file;
  std::tie(code, out) = shell(cli + " list" + server);
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("succeeded"), std::string::npos) << out;
  std::tie(code, out) = shell(cli + " cancel " + std::to_string(id) + server);
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("409"), std::string::npos) << out;
  std::tie(code, out) = shell(cli + " status 4242" + server);
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("404"), std::string::npos) << out;
  std::tie(code, out) = shell(cli + " list --owner nobody" + server);
  EXPECT_EQ(code, 0);
  EXPECT_EQ(out, "");
  std::tie(code, out) = shell(cli + " priority " + std::to_string(id) + " --priority 3" + server);
  EXPECT_EQ(code, 1);  // finished: no longer queued
  EXPECT_NE(out.find("409"), std::string::npos) << out;
  std::tie(code, out) = shell(cli + " delete " + std::to_string(id) + server);
  EXPECT_EQ(code, 0) << out;
  // The results of a job that did not succeed: what it computed, no summary, exit 1 saying why.
  const std::int64_t cancelled = post("/v1/jobs", R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
    "loading": {"rate_number": 1e-8}, "output": {"curve_points": 1}})",
                                      201)["id"];
  for (int k = 0; k < 500 && get("/v1/jobs/" + std::to_string(cancelled))["status"] != "running"; ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  post("/v1/jobs/" + std::to_string(cancelled) + "/cancel", "", 202);
  ASSERT_EQ(wait(cancelled, 5)["status"], "cancelled");
  std::tie(code, out) =
      shell(cli + " results " + std::to_string(cancelled) + " --out " + (dir_ / "partial").string() + server);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("is cancelled"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(dir_ / "partial" / "curve.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "partial" / "summary.json"));
  std::tie(code, out) = shell(cli + " status " + std::to_string(id) + server);
  EXPECT_NE(out.find("404"), std::string::npos) << out;
}

// submit --json and --dry-run; wait on several jobs; a sweep from the command line with its table and folders;
// results of a crystal with its snapshots in every format.
TEST_F(Daemon, CliSweepWaitDryRunAndResultsInEveryFormat) {
  pool_->start();
  const std::string cli = std::string(GRANULAB_BINARY_DIR) + "/granulab";
  const std::string server = " --server http://127.0.0.1:" + std::to_string(port_);
  const fs::path spec = dir_ / "spec.json";
  std::ofstream(spec) << kTwoCube;

  auto [code, out] = shell(cli + " submit " + spec.string() + " --json" + server);
  ASSERT_EQ(code, 0) << out;
  const std::int64_t first = json::parse(out)["id"];
  std::tie(code, out) = shell(cli + " submit " + spec.string() + " --dry-run" + server);
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("two_cube_sliding: "), std::string::npos) << out;
  EXPECT_NE(out.find("once started"), std::string::npos) << out;
  std::tie(code, out) = shell(cli + " submit " + spec.string() + " --dry-run --json" + server);
  const json cost = json::parse(out);
  EXPECT_TRUE(cost["dry_run"].get<bool>());
  EXPECT_GT(cost["expected_seconds"].get<double>(), 0);
  EXPECT_TRUE(cost["grains"].is_number_integer() && cost["spheres"].is_number_integer()) << cost.dump();  // counts
  EXPECT_EQ(get("/v1/jobs?limit=1000")["jobs"].size(), 1u) << "a dry run queued a job";

  // wait on two jobs: one line each at the end, exit 0 when both succeeded.
  std::tie(code, out) = shell(cli + " submit " + spec.string() + server);
  const std::int64_t second = std::stoll(out);
  std::tie(code, out) = shell(cli + " wait " + std::to_string(first) + " " + std::to_string(second) + server);
  EXPECT_EQ(code, 0) << out;
  for (std::int64_t id : {first, second}) EXPECT_NE(out.find("job " + std::to_string(id)), std::string::npos) << out;
  EXPECT_NE(out.find("succeeded [####################] 100.0 %"), std::string::npos) << out;

  // A sweep: 2 x 2 jobs, sweep.csv with a row each and the varied values, a folder per job with its curve.
  std::tie(code, out) =
      shell(cli + " sweep " + spec.string() + " --vary material.friction=0.1,0.3 --vary loading.max_slide=0.2,0.4" +
            " --label cli --out " + (dir_ / "sweep").string() + server);
  ASSERT_EQ(code, 0) << out;
  std::ifstream table(dir_ / "sweep" / "sweep.csv");
  std::vector<std::string> rows;
  for (std::string line; std::getline(table, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0].rfind("id,loading.max_slide,material.friction,status,", 0), 0u) << rows[0];
  std::set<std::string> points;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    std::stringstream cells(rows[r]);
    std::string id, slide, friction, status;
    std::getline(cells, id, ','), std::getline(cells, slide, ','), std::getline(cells, friction, ','),
        std::getline(cells, status, ',');
    EXPECT_EQ(status, "succeeded") << rows[r];
    points.insert(slide + "/" + friction);
    const json job = get("/v1/jobs/" + id);
    EXPECT_EQ(job["spec"]["loading"]["max_slide"].dump(), slide);
    EXPECT_EQ(job["spec"]["material"]["friction"].dump(), friction);
    EXPECT_TRUE(fs::exists(dir_ / "sweep" / id / "curve.csv")) << id;
    EXPECT_TRUE(fs::exists(dir_ / "sweep" / id / "summary.json")) << id;
  }
  EXPECT_EQ(points, (std::set<std::string>{"0.2/0.1", "0.2/0.3", "0.4/0.1", "0.4/0.3"}));
  std::tie(code, out) = shell(cli + " sweep " + spec.string() + " --vary material.friction=0.1,99 --out " +
                              (dir_ / "bad").string() + server);
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("vary.material.friction"), std::string::npos) << out;

  // results of a crystal: every snapshot in the four formats, as `granulab run` names them.
  const std::int64_t crystal = post("/v1/jobs", R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
    "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2}, "loading": {"confining_pressure": 30e3, "max_strain": 2e-3,
    "rate_number": 1e-4}, "output": {"curve_points": 5, "snapshot_strains": [0, 2e-3]}})",
                                    201)["id"];
  ASSERT_EQ(wait(crystal)["status"], "succeeded");
  std::tie(code, out) =
      shell(cli + " results " + std::to_string(crystal) + " --out " + (dir_ / "crystal").string() + server);
  ASSERT_EQ(code, 0) << out;
  for (int k : {0, 1})
    for (const char* suffix : {".json", ".dump", "_grains.vtk", "_interfaces.vtk", "_contacts.vtk", "_contacts.dump", "_meshes.vtk", "_dic.csv", "_dic.vtk"}) {
      const fs::path file = dir_ / "crystal" / "snapshots" / ("snapshot_" + std::to_string(k) + suffix);
      EXPECT_TRUE(fs::exists(file) && fs::file_size(file) > 100) << file;
    }
}

}  // namespace
}  // namespace granulab::server

namespace granulab::server {
namespace {

// Long enough (a few seconds) that the curve can be watched while it grows.
const char* kSlowCrystal = R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
  "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
  "loading": {"confining_pressure": 30e3, "max_strain": 0.03, "rate_number": 2e-6},
  "output": {"curve_points": 200, "snapshot_strains": [0.0, 0.01, 0.02]}})";

std::size_t rows_of(const std::string& csv) { return std::count(csv.begin(), csv.end(), '\n') - 1; }

// A running job's curve is served as it grows (rows reach the store in batches, every 0.05 s here), each
// view a prefix of the final curve; snapshots appear as they are taken; a job cancelled midway keeps the
// rows it computed, identical to the same rows of a complete run.
TEST_F(Daemon, LiveCurveGrowsAndACancelledJobKeepsItsRows) {
  pool_->start();
  const std::string path = "/v1/jobs/" + std::to_string(post("/v1/jobs", kSlowCrystal, 201)["id"].get<std::int64_t>());
  std::vector<std::string> seen;  // distinct partial curves seen while the job ran
  std::size_t snapshots_while_running = 0;
  for (auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
       std::chrono::steady_clock::now() < until;) {
    const std::string status = get(path)["status"];
    if (status == "succeeded" || status == "failed") break;
    auto r = client_->Get((path + "/curve?format=csv").c_str());
    ASSERT_TRUE(r);
    if (status == "running" && r->status == 200 && (seen.empty() || r->body != seen.back())) {
      if (get(path)["status"] == "running") {
        seen.push_back(r->body);
        snapshots_while_running = std::max(snapshots_while_running, get(path + "/snapshots")["snapshots"].size());
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(get(path)["status"], "succeeded");
  auto final_csv = client_->Get((path + "/curve?format=csv").c_str());
  ASSERT_TRUE(final_csv);
  const std::size_t total = rows_of(final_csv->body);
  EXPECT_GT(total, 150u);
  ASSERT_GE(seen.size(), 3u) << "the curve was not seen growing while the job ran";
  for (std::size_t k = 0; k < seen.size(); ++k) {
    EXPECT_EQ(final_csv->body.compare(0, seen[k].size(), seen[k]), 0) << "view " << k << " is not a prefix";
    if (k) {
      EXPECT_GT(rows_of(seen[k]), rows_of(seen[k - 1]));
    }
  }
  EXPECT_LT(rows_of(seen.front()), total);
  EXPECT_GE(snapshots_while_running, 1u);
  // The JSON form while running has the same columns.
  EXPECT_EQ(get(path + "/curve")["columns"][0], "strain");

  // The same spec again, cancelled once it has some rows: it keeps them.
  const std::string second =
      "/v1/jobs/" + std::to_string(post("/v1/jobs", kSlowCrystal, 201)["id"].get<std::int64_t>());
  for (auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
       std::chrono::steady_clock::now() < until;) {
    auto r = client_->Get((second + "/curve?format=csv").c_str());
    if (r && r->status == 200 && rows_of(r->body) >= 10) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  post(second + "/cancel", "", 202);
  ASSERT_EQ(wait(std::stoll(second.substr(9)))["status"], "cancelled");
  auto kept = client_->Get((second + "/curve?format=csv").c_str());
  ASSERT_TRUE(kept);
  ASSERT_EQ(kept->status, 200);
  EXPECT_GE(rows_of(kept->body), 10u);
  EXPECT_LT(rows_of(kept->body), total);
  EXPECT_EQ(final_csv->body.compare(0, kept->body.size(), kept->body), 0);
  EXPECT_EQ(get(second + "/curve")["strain"].size(), rows_of(kept->body));
}

// A two-cube job with one curve point is one long stretch of steps (about 4e8 here): a cancel and a
// shutdown still reach it within a second, and a cancel survives a restart instead of being rerun.
TEST_F(Daemon, CancelAndStopReachAOnePointJobWithinASecond) {
  const char* one_point = R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
    "loading": {"rate_number": 1e-8}, "output": {"curve_points": 1}})";
  pool_->start();
  const auto running = [&](std::int64_t id) {
    for (int k = 0; k < 500 && get("/v1/jobs/" + std::to_string(id))["status"] != "running"; ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  };
  const std::int64_t cancelled = post("/v1/jobs", one_point, 201)["id"];
  running(cancelled);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  auto t0 = std::chrono::steady_clock::now();
  post("/v1/jobs/" + std::to_string(cancelled) + "/cancel", "", 202);
  EXPECT_EQ(wait(cancelled, 5)["status"], "cancelled");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);

  const std::int64_t stopped = post("/v1/jobs", one_point, 201)["id"];
  running(stopped);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  t0 = std::chrono::steady_clock::now();
  pool_->stop();  // what SIGTERM does
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
  EXPECT_EQ(get("/v1/jobs/" + std::to_string(stopped))["status"], "running");  // granulabd re-queues it
}

// A checkpoint that does not match the stored results (here: it follows 5 rows, the store holds none) is
// not resumed from: the job starts afresh and its curve is the direct run's.
TEST_F(Daemon, AMismatchedCheckpointStartsTheJobAfresh) {
  struct FirstCheckpoint : api::MemorySink {
    std::string state;
    bool checkpoint_due() override { return state.empty(); }
    void checkpoint(const CheckpointContent& c, std::size_t, std::size_t) override { state = checkpoint_bytes(c); }
  } capture;
  api::run(api::parse_spec_text(kTwoCube), capture);
  ASSERT_FALSE(capture.state.empty());
  const std::int64_t id = post("/v1/jobs", kTwoCube, 201)["id"];
  ASSERT_EQ(store_->claim_next()->id, id);
  store_->start_curve(id, "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force\n");
  const JobStore::Checkpoint cp{store_->begin_checkpoint(id), 1, std::int64_t(capture.state.size()), 5, 0,
                                api::engine_version()};
  ASSERT_TRUE(store_->put_checkpoint_chunk(id, cp.generation, 0, capture.state.data(), capture.state.size()));
  store_->append_results(id, 0, {}, {}, &cp);
  store_->end_checkpoint_write(id, cp.generation);
  ASSERT_EQ(store_->requeue_running(), 1u);
  pool_->start();
  ASSERT_EQ(wait(id)["status"], "succeeded");
  auto csv = client_->Get(("/v1/jobs/" + std::to_string(id) + "/curve?format=csv").c_str());
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->body, api::run_spec(api::parse_spec_text(kTwoCube)).curve_csv);
}

// The registry, as clients see it.
TEST_F(Daemon, ExperimentsAreDescribedFromTheRegistry) {
  const json e = get("/v1/experiments");
  ASSERT_EQ(e["experiments"].size(), experiment_types().size());
  for (std::size_t k = 0; k < experiment_types().size(); ++k) {
    EXPECT_EQ(e["experiments"][k]["name"], experiment_types()[k].name);
    EXPECT_FALSE(e["experiments"][k]["fields"].empty());
    EXPECT_FALSE(e["experiments"][k]["curve_columns"].empty());
  }
}

}  // namespace
}  // namespace granulab::server

namespace granulab::server {
namespace {

// engine_version as cmake/engine_version.cmake computes it for a source tree (copies of engine/ and api/).
std::string version_of(const fs::path& tree, const fs::path& work) {
  const fs::path out = work / "engine_source_version.cpp";
  const auto [code, log] =
      shell(std::string(GRANULAB_CMAKE) + " -DSOURCE_DIR=" + tree.string() + " -DOUTPUT=" + out.string() +
            " -DVERSION=" + GRANULAB_VERSION + " -P " + GRANULAB_SOURCE_DIR + "/cmake/engine_version.cmake");
  EXPECT_EQ(code, 0) << log;
  std::ifstream in(out);
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string s = text.str();
  return std::regex_search(s, m, std::regex(R"re(return "([^"]+)")re")) ? m[1].str() : "";
}

// The reuse key follows the sources: this build's engine_version is the hash of its engine/ and api/
// sources; a build of sources that differ by one line has another version; a stored result of that other
// build is not served by ?reuse=true here, one of this build is.
TEST_F(Daemon, BuildsOfDifferentEngineSourcesDoNotShareResults) {
  const fs::path tree = dir_ / "tree";
  fs::create_directories(tree);
  for (const char* part : {"engine", "api"})
    fs::copy(fs::path(GRANULAB_SOURCE_DIR) / part, tree / part, fs::copy_options::recursive);
  const std::string ours = version_of(tree, dir_);
  EXPECT_EQ(ours, api::engine_source_version()) << "the build did not use cmake/engine_version.cmake on these sources";
  // The version results carry names the contact kernel too: kernels may differ in their last bits.
  EXPECT_EQ(api::engine_version(), ours + "." + resolve_pair_kernel(""));
  std::ofstream(tree / "engine" / "contact" / "contact_law.h", std::ios::app) << "// a change to the physics\n";
  const std::string theirs = version_of(tree, dir_);
  ASSERT_FALSE(theirs.empty());
  EXPECT_NE(theirs, ours);

  const api::Spec spec = api::parse_spec_text(kTwoCube);
  const std::string hash = api::spec_hash(spec.normalized);
  auto stored_result = [&](const std::string& version) {
    const std::int64_t id = store_->submit(spec.normalized.dump(), spec.name(), "", hash, version, "", 0);
    EXPECT_EQ(store_->claim_next()->id, id);
    EXPECT_TRUE(store_->succeed(id, R"({"steps": 1})", "a\n1\n", R"({"columns": ["a"], "a": [1]})"));
    return id;
  };
  stored_result(theirs);
  const json fresh = post("/v1/jobs?reuse=true", kTwoCube, 201);  // the other build's result is not served
  EXPECT_EQ(fresh["status"], "queued");
  ASSERT_EQ(post("/v1/jobs/" + std::to_string(fresh["id"].get<std::int64_t>()) + "/cancel", "", 200)["status"],
            "cancelled");
  // A result of this build's sources by another contact kernel (a node of another CPU) is not served either.
  const std::string other_kernel = ours + (resolve_pair_kernel("") == kBaselineKernel ? ".avx2" : "." + std::string(kBaselineKernel));
  stored_result(other_kernel);
  const json other = post("/v1/jobs?reuse=true", kTwoCube, 201);
  EXPECT_EQ(other["status"], "queued");
  ASSERT_EQ(post("/v1/jobs/" + std::to_string(other["id"].get<std::int64_t>()) + "/cancel", "", 200)["status"],
            "cancelled");
  const std::int64_t mine = stored_result(api::engine_version());
  const json reused = post("/v1/jobs?reuse=true", kTwoCube, 200);
  EXPECT_EQ(reused["id"], mine);
}

}  // namespace
}  // namespace granulab::server

namespace granulab::server {
namespace {

// Requests that once crashed the daemon or made it answer 500 with the exception's text: each gets its
// documented status, a JSON error, and the daemon keeps serving.
TEST_F(Daemon, HostileInputGetsAnAnswerNotACrash) {
  struct Case {
    std::string method, path, body;
    int status;
    std::string code, field;
  };
  const std::string deep = std::string(30000, '[') + std::string(30000, ']');  // 60 KB, under this daemon's 64 KB
  const std::vector<Case> cases = {
      {"POST", "/v1/jobs", deep, 400, "too_deep", ""},
      {"POST", "/v1/jobs", "{\"label\": \"caf\xe9\"}", 400, "invalid_json", ""},
      {"POST", "/v1/jobs", R"({"grain": {"size": 1e400}})", 400, "out_of_range", "grain.size"},
      {"POST", "/v1/jobs", R"({"material": {"friction": -1e400}})", 400, "out_of_range", "material.friction"},
      {"GET", "/v1/jobs/123456789012345678901", "", 404, "not_found", ""},
      {"GET", "/v1/jobs/99999999999999999999/curve", "", 404, "not_found", ""},
      {"POST", "/v1/jobs/99999999999999999999/cancel", "", 404, "not_found", ""},
      {"GET", "/v1/jobs/1/snapshots/4294967296", "", 404, "not_found", ""},
      {"GET", "/v1/jobs/1/snapshots/99999999999999999999999", "", 404, "not_found", ""},
      {"GET", "/v1/jobs?limit=%FF", "", 400, "out_of_range", "limit"},
      {"GET", "/v1/jobs?offset=99999999999999999999", "", 400, "out_of_range", "offset"},
      {"GET", "/v1/jobs?status=%FF%FE", "", 400, "invalid_value", "status"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.method + " " + c.path.substr(0, 60));
    auto r =
        c.method == "GET" ? client_->Get(c.path.c_str()) : client_->Post(c.path.c_str(), c.body, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, c.status) << r->body.substr(0, 300);
    const json e = json::parse(r->body);  // valid JSON, whatever the request held
    EXPECT_EQ(e["error"]["code"], c.code) << r->body.substr(0, 300);
    if (!c.field.empty()) {
      EXPECT_EQ(e["error"]["field"], c.field);
    }
  }
  EXPECT_EQ(get("/v1/health")["status"], "ok");
}

// Whatever a handler throws (here: a stored spec that is not JSON, as a damaged file could hold) becomes a
// JSON 500 with a request id, and the exception's text stays in the log.
TEST_F(Daemon, AnythingAHandlerThrowsIsAJson500WithoutTheExceptionText) {
  const std::int64_t id = store_->submit("{not json", "two_cube_sliding", "", "", "", "", 0);
  auto r = client_->Get(("/v1/jobs/" + std::to_string(id)).c_str());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 500);
  const json e = json::parse(r->body);
  EXPECT_EQ(e["error"]["code"], "internal");
  EXPECT_EQ(r->body.find("parse_error"), std::string::npos) << r->body;
  EXPECT_NE(r->get_header_value("X-Request-Id"), "");
  EXPECT_NE(e["error"]["message"].get<std::string>().find(r->get_header_value("X-Request-Id")), std::string::npos);
  EXPECT_EQ(get("/v1/health")["status"], "ok");
}

}  // namespace
}  // namespace granulab::server

namespace granulab::server {
namespace {

// Requests on one kept-alive connection do not wait for the client's delayed ACK (Nagle): 100 of them
// took 2.6 s before TCP_NODELAY (26 ms each), 0.02 s after. The bound leaves a 100x margin for a slow machine.
TEST_F(Daemon, KeptAliveRequestsDoNotStall) {
  httplib::Client c("127.0.0.1", port_);
  c.set_keep_alive(true);
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < 100; ++k) {
    auto r = c.Get("/v1/health");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200);
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
}

}  // namespace
}  // namespace granulab::server
